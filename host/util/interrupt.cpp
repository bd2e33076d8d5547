// SIGINT/SIGTERM/SIGHUP -> a flag; see interrupt.h.
#include "host/util/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <initializer_list>

namespace lorgnette {
namespace {
std::atomic<int> g_signals{0};

extern "C" void on_signal(int) {
  if (g_signals.fetch_add(1) >= 1) _exit(130);
  // One notice for every command: each stops at its own next safe point and then says what it kept
  // (train: the model so far and its checkpoint; render: the whole frames written; the others: nothing).
  const char msg[] = "\ninterrupted: stopping at the next safe point (Ctrl-C again to abort at once)\n";
  ssize_t ignored = write(2, msg, sizeof(msg) - 1);
  (void)ignored;
}
}  // namespace

void install_interrupt_handler() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // reads and writes in progress carry on; loops poll the flag
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &action, nullptr);
}
bool interrupted() { return g_signals.load() > 0; }
void request_interrupt() {
  int none = 0;
  g_signals.compare_exchange_strong(none, 1);
}
void clear_interrupt() { g_signals.store(0); }

}  // namespace lorgnette
