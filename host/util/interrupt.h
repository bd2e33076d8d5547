// Ctrl-C handling for long work: the first SIGINT/SIGTERM sets a flag that loops poll (so they can
// save a snapshot and stop cleanly); a second one exits at once.
#pragma once

namespace lorgnette {

void install_interrupt_handler();
bool interrupted();
// Sets the flag as a first Ctrl-C would (no message): loops stop at their next poll, e.g. when a
// Python progress callback asks training to stop.
void request_interrupt();
void clear_interrupt();  // for tests

}  // namespace lorgnette
