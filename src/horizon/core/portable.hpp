#pragma once
// Device-portable functions (issue 30): the explicit step's per-bond and per-particle
// work is written as plain functions over flat arrays, marked HORIZON_HD, so that the
// host build and a CUDA build (nvcc, -DHORIZON_CUDA=ON) compile the same source. Inside
// such a function: no virtual calls, no std containers, no exceptions, no allocation.
#if defined(__CUDACC__)
#define HORIZON_HD __host__ __device__
#else
#define HORIZON_HD
#endif

// A portable function that a hot row calls once per bond, inlined whatever the compiler's
// estimate: out of line, extended correspondence's pair-sum term (kernels/extended.hpp
// pair_bond) cost its AVX-512 row 20 % (docs/benchmarks.md, 2026-11-29, kernels30).
#if defined(__CUDACC__)
#define HORIZON_HD_INLINE __host__ __device__ __forceinline__
#elif defined(__GNUC__) || defined(__clang__)
#define HORIZON_HD_INLINE __attribute__((always_inline)) inline
#else
#define HORIZON_HD_INLINE inline
#endif
