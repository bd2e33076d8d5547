// Ctrl-C handling for long work: the first SIGINT/SIGTERM sets a flag that loops poll (so they can
// save a snapshot and stop cleanly); a second one exits at once.
#pragma once

namespace lorgnette {

void install_interrupt_handler();
bool interrupted();
void clear_interrupt();  // for tests

}  // namespace lorgnette
