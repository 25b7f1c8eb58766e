// Ctrl-C (SIGINT) during a calibration wizard: while a guard lives, the signal
// sets a flag the wizard polls (to stop the devices where they are and keep the
// samples taken) instead of ending the process; the previous handler is back
// when the guard goes.
#pragma once

namespace aerograsp {

class InterruptGuard {
 public:
  InterruptGuard();  ///< clears the flag and installs the handler
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  /// True once SIGINT arrived while a guard was installed.
  static bool Interrupted();

 private:
  void (*previous_)(int);
};

}  // namespace aerograsp
