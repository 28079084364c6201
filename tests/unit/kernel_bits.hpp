#pragma once
// Bit-for-bit comparison of the portable kernels' row-major double[9] with the Eigen
// matrices of the host forms they replace (test_affine_kernels, test_law_kernels,
// test_hencky_kernels).
#include <Eigen/Dense>
#include <cstring>

namespace horizon::test {

using Mat3 = Eigen::Matrix3d;

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// m into row-major a[9].
inline void to_rows(const Mat3& m, double* a) {
  for (int c = 0; c < 9; ++c) a[c] = m(c / 3, c % 3);
}

// How many of the nine entries of the row-major a differ in any bit from m's.
inline int differing(const Mat3& m, const double* a) {
  int n = 0;
  for (int c = 0; c < 9; ++c) n += same_bits(m(c / 3, c % 3), a[c]) ? 0 : 1;
  return n;
}

}  // namespace horizon::test
