// Checks of command-line numbers where they enter (CLI11 validators), so that
// a NaN, an infinity, a value out of range or a negative seed is refused with
// the option named ("--sway: nan is not a finite number") instead of reaching
// the code. Every numeric option of the command line uses one of these.
#pragma once

namespace CLI {
class Validator;
}

namespace aerograsp::cli {

/// A finite number in [min, max] (CLI::Range lets NaN through).
CLI::Validator Range(double min, double max);
/// Any finite number.
CLI::Validator Finite();
/// A seed: a whole number from 0 to 2^64 - 1 (an unsigned option would turn
/// "-5" into 18446744073709551611).
CLI::Validator Seed();

}  // namespace aerograsp::cli
