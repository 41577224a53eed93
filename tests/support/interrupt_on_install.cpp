// A library for LD_PRELOAD in the tests: it raises SIGINT in the process right after the process
// installs its first SIGINT handler that is a function (dacrt's StopOnSignals, which a render
// installs once its scene is loaded). A test can so interrupt a render at a known point, before
// its first sample, without timing anything.
#include <dlfcn.h>

#include <csignal>

extern "C" int sigaction(int sig, const struct sigaction* act, struct sigaction* old) {
  using Sigaction = int (*)(int, const struct sigaction*, struct sigaction*);
  static const auto real = reinterpret_cast<Sigaction>(dlsym(RTLD_NEXT, "sigaction"));
  static bool raised = false;
  const int result = real(sig, act, old);
  if (result == 0 && sig == SIGINT && act && !raised && act->sa_handler != SIG_DFL &&
      act->sa_handler != SIG_IGN) {
    raised = true;
    std::raise(SIGINT);
  }
  return result;
}
