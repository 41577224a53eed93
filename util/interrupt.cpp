#include "dacrt/util/interrupt.h"

#include <csignal>

#include "dacrt/util/atomic_file.h"

namespace dacrt {

namespace {

std::atomic<bool> stop_requested{false};
volatile std::sig_atomic_t received = 0;
struct sigaction previous_int, previous_term;

extern "C" void request_stop(int sig) {
  if (received) {  // the second: end now
    remove_pending_file();
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  received = sig;
  stop_requested.store(true);
}

}  // namespace

StopOnSignals::StopOnSignals() {
  static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");
  stop_requested = false;
  received = 0;
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previous_int);
  sigaction(SIGTERM, &action, &previous_term);
}

StopOnSignals::~StopOnSignals() {
  sigaction(SIGINT, &previous_int, nullptr);
  sigaction(SIGTERM, &previous_term, nullptr);
}

const std::atomic<bool>& StopOnSignals::token() const {
  return stop_requested;
}

int StopOnSignals::signal() const {
  return received;
}

}  // namespace dacrt
