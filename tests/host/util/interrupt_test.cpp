// Signals stop long work the way Ctrl-C does (host/util/interrupt.h): SIGINT, SIGTERM and SIGHUP
// set the flag loops poll; a second signal of any kind ends the process at once with status 130.
#include "host/util/interrupt.h"

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>

namespace lorgnette {
namespace {

TEST(Interrupt, TermAndHangupStopLikeCtrlC) {
  install_interrupt_handler();
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    clear_interrupt();
    EXPECT_FALSE(interrupted());
    std::raise(sig);  // the default action would end this test process
    EXPECT_TRUE(interrupted()) << "signal " << sig;
  }
  clear_interrupt();
}

TEST(Interrupt, ASecondSignalEndsTheProcessAtOnce) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        install_interrupt_handler();
        std::raise(SIGTERM);
        std::raise(SIGHUP);
        std::exit(0);  // not reached: the second signal exits with 130
      },
      ::testing::ExitedWithCode(130), "interrupted");
}

}  // namespace
}  // namespace lorgnette
