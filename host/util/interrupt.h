// Stopping long work: the first SIGINT (Ctrl-C), SIGTERM (a service stopping the process) or SIGHUP
// (its terminal closed) sets a flag that loops poll, so they can save a snapshot and stop cleanly;
// a second one of any of them exits at once (status 130).
#pragma once

namespace lorgnette {

void install_interrupt_handler();
bool interrupted();
// Sets the flag as a first Ctrl-C would (no message): loops stop at their next poll, e.g. when a
// Python progress callback asks training to stop.
void request_interrupt();
void clear_interrupt();  // for tests

}  // namespace lorgnette
