// Runs a scope on one OpenMP thread. For tests whose figures do not depend on the thread
// count (test_threads.cpp checks that they never do) and that open hundreds of tiny
// parallel regions: on a shared, oversubscribed machine each two-thread barrier can cost
// a scheduler time slice, seconds in all.
#pragma once

#include <omp.h>

namespace horizon::test {

class SingleThread {
 public:
  SingleThread() : saved_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~SingleThread() { omp_set_num_threads(saved_); }
  SingleThread(const SingleThread&) = delete;
  SingleThread& operator=(const SingleThread&) = delete;

 private:
  int saved_;
};

}  // namespace horizon::test
