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
