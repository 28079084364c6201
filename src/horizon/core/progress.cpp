#include "horizon/core/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>

namespace horizon {

std::string format_duration(double s) {
  if (s < 60) return fmt::format("{:.1f}s", s);
  if (s < 3600) return fmt::format("{}m{:02d}s", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  return fmt::format("{}h{:02d}m", static_cast<int>(s / 3600), static_cast<int>(s / 60) % 60);
}

Progress::Progress(int64_t total_steps, double bonds, int64_t plain_every, std::FILE* out)
    : total_(std::max<int64_t>(1, total_steps)),
      bonds_(bonds),
      plain_every_(plain_every > 0 ? plain_every : std::max<int64_t>(1, total_steps / 10)),
      out_(out),
      tty_(isatty(fileno(out)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::update(int64_t step, double time) {
  const auto now = std::chrono::steady_clock::now();
  const bool plain_due = !tty_ && (step % plain_every_ == 0 || step == total_);
  const bool tty_due = tty_ && (std::chrono::duration<double>(now - last_draw_).count() > 0.2 || step == total_);
  if (!plain_due && !tty_due) return;
  last_draw_ = now;
  const double el = elapsed();
  const double frac = static_cast<double>(step) / static_cast<double>(total_);
  const double eta = frac > 0 ? el * (1 - frac) / frac : 0;
  const double rate = el > 0 ? bonds_ * static_cast<double>(step) / el : 0;
  const std::string line = fmt::format("step {:>8}/{}  t = {:.4e} s  {:5.1f}%  ETA {:>7}  {:.3g} bond updates/s", step,
                                       total_, time, 100 * frac, format_duration(eta), rate);
  if (tty_)
    fmt::print(out_, "\r{}\x1b[K", line);
  else
    fmt::print(out_, "{}\n", line);
  std::fflush(out_);
}

void Progress::finish() {
  if (tty_) fmt::print(out_, "\n");
  std::fflush(out_);
}

}  // namespace horizon
