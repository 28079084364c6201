#pragma once
// The indices k in [0, n) with pred(k), in increasing order, found by the OpenMP threads.
// Each thread scans one contiguous chunk and the chunks are joined in order, so a serial
// loop over the result visits the selected indices in the order a serial loop over all n
// would: a sum over them has the bits of the serial sum that skipped the others. It takes
// the per-step scans of every particle (rigid contact candidates, loaded particles) off
// the single thread (docs/benchmarks.md, "Sixteen cores").
#include <cstddef>
#include <cstdint>
#include <vector>

#include <omp.h>

namespace horizon {

template <class Pred>
std::vector<uint32_t> parallel_select(std::size_t n, Pred pred) {
  const int most = omp_get_max_threads();
  std::vector<std::vector<uint32_t>> part(static_cast<std::size_t>(most));
#pragma omp parallel
  {
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
    const auto nt = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t begin = n * t / nt, end = n * (t + 1) / nt;
    auto& mine = part[t];
    for (std::size_t k = begin; k < end; ++k)
      if (pred(k)) mine.push_back(static_cast<uint32_t>(k));
  }
  std::size_t total = 0;
  for (const auto& p : part) total += p.size();
  std::vector<uint32_t> out;
  out.reserve(total);
  for (const auto& p : part) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// dst = src, copied by the OpenMP threads (the per-step copies of the state).
template <class T>
void parallel_copy(std::vector<T>& dst, const std::vector<T>& src) {
  dst.resize(src.size());
  const std::size_t n = src.size();
  T* d = dst.data();
  const T* s = src.data();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) d[k] = s[k];
}

// Every entry of v set to x by the OpenMP threads.
template <class T>
void parallel_fill(std::vector<T>& v, const T& x) {
  const std::size_t n = v.size();
  T* d = v.data();
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) d[k] = x;
}

}  // namespace horizon
