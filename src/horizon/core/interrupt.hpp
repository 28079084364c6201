#pragma once
// Ctrl-C: the first SIGINT (or SIGTERM) asks the run to stop after the current step,
// write a final frame and a valid index, and exit non-zero. A second one kills.
namespace horizon {

void install_interrupt_handler();
bool interrupt_requested();
void clear_interrupt();

}  // namespace horizon
