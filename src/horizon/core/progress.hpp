#pragma once
// The progress line: on a terminal it is redrawn in place; otherwise a plain line is
// printed every so often, so logs stay readable.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace horizon {

class Progress {
 public:
  // total_steps > 0; bonds: directed bonds per step, for the throughput figure.
  Progress(int64_t total_steps, double bonds, int64_t plain_every, std::FILE* out = stderr);
  void update(int64_t step, double time);
  void finish();
  double elapsed() const;

 private:
  int64_t total_;
  double bonds_;
  int64_t plain_every_;
  std::FILE* out_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

std::string format_duration(double seconds);

}  // namespace horizon
