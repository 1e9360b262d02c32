// SIGINT and SIGTERM during a run (see Interrupt.h).
#include "Interrupt.h"

#include <csignal>

namespace ldae::driver {

namespace {

volatile std::sig_atomic_t gReceived = 0;
struct sigaction gOldInt, gOldTerm;

void onSignal(int sig) { gReceived = sig; }

} // namespace

InterruptGuard::InterruptGuard() {
  gReceived = 0;
  struct sigaction sa{};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &gOldInt);
  sigaction(SIGTERM, &sa, &gOldTerm);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &gOldInt, nullptr);
  sigaction(SIGTERM, &gOldTerm, nullptr);
}

int InterruptGuard::received() { return gReceived; }

} // namespace ldae::driver
