#pragma once
// Ctrl-C: the first SIGINT (or SIGTERM) asks the run to stop after the current step,
// write a final frame and a valid index, and exit with 128 + the signal's number (130
// for SIGINT, 143 for SIGTERM, as a shell reports a process those signals killed). A
// second one kills.
namespace horizon {

void install_interrupt_handler();
bool interrupt_requested();
int interrupt_signal();       // the last signal received, 0 if none
int interrupt_exit_code();    // 128 + that signal
const char* interrupt_name();  // "SIGINT" or "SIGTERM"
void clear_interrupt();

}  // namespace horizon
