#include "app/calibration/interrupt_guard.h"

#include <csignal>

namespace aerograsp {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void OnInterrupt(int) { g_interrupted = 1; }

}  // namespace

InterruptGuard::InterruptGuard() : previous_(std::signal(SIGINT, OnInterrupt)) {
  g_interrupted = 0;
}

InterruptGuard::~InterruptGuard() { std::signal(SIGINT, previous_); }

bool InterruptGuard::Interrupted() { return g_interrupted != 0; }

}  // namespace aerograsp
