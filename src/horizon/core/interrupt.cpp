#include "horizon/core/interrupt.hpp"

#include <atomic>
#include <csignal>

namespace horizon {

namespace {
std::atomic<int> g_interrupts{0};
std::atomic<int> g_signal{0};

extern "C" void on_signal(int sig) {
  g_signal.store(sig);
  if (g_interrupts.fetch_add(1) >= 1) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}
}  // namespace

void install_interrupt_handler() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

bool interrupt_requested() { return g_interrupts.load() > 0; }
int interrupt_signal() { return g_signal.load(); }
int interrupt_exit_code() {
  const int sig = g_signal.load();
  return 128 + (sig ? sig : SIGINT);
}
const char* interrupt_name() { return g_signal.load() == SIGTERM ? "SIGTERM" : "SIGINT"; }
void clear_interrupt() { g_interrupts.store(0); }

}  // namespace horizon
