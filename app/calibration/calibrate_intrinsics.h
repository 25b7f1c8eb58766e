// `aerograsp calibrate --intrinsics`: the camera's intrinsics from views of a
// tag board, to check the factory values; `--resolve DIR` solves again from
// the saved views. Without `--hardware` the simulator shows the board in
// planned views; with `--hardware CONFIG` a person holds the board in front of
// the camera (real or simulated) and the wizard takes the samples it needs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <istream>
#include <memory>
#include <ostream>
#include <string>

#include "app/calibration/calibrate_command.h"
#include "app/calibration/calibration_hardware.h"
#include "calib/coverage.h"
#include "calib/tag_board.h"
#include "hardware/hardware_config.h"

namespace aerograsp {

class World;
class RgbdCamera;

/// The board the intrinsics wizard shows: 4 x 5 tag36h11 tags of 30 mm
/// (0.202 x 0.164 m): 80 corners, half the image's width at 0.4 m.
TagBoardConfig IntrinsicsBoard();

/// The camera of a hand-held intrinsics run (`--hardware CONFIG`), opened by
/// OpenIntrinsicsHardware. Simulated ('sim' camera), the world carries the
/// board held in front of the camera (its attachment moved by whoever plays
/// the hand); on the real camera world() is null.
class IntrinsicsHardware {
 public:
  ~IntrinsicsHardware();
  IntrinsicsHardware(const IntrinsicsHardware&) = delete;
  IntrinsicsHardware& operator=(const IntrinsicsHardware&) = delete;

  const HardwareConfig& config() const { return config_; }
  /// The board held: the hardware file's `calibration.board` when its
  /// `calibration.mount` is 'hand', else IntrinsicsBoard().
  const TagBoardConfig& board() const { return board_; }
  /// The hardware file's `calibration` section (the hand-held run's limits).
  const CalibrationRig& rig() const { return rig_; }
  const std::string& camera_name() const { return camera_name_; }
  RgbdCamera& camera() { return *camera_; }
  World* world() { return world_.get(); }
  /// The board's attachment in world() (for World::MoveAttachment).
  std::size_t board_attachment() const { return board_attachment_; }
  /// Simulated: called after every world step with the world's time, s (the
  /// hand that moves the board in a test).
  void SetSimulatedHand(std::function<void(IntrinsicsHardware&, double t_s)> hand) {
    hand_ = std::move(hand);
  }
  /// Until the next frame: simulated, one frame period (camera.fps) of world
  /// time and the hand's move; on the camera, nothing (Grab waits for the frame).
  void WaitForFrame();

 private:
  friend std::unique_ptr<IntrinsicsHardware> OpenIntrinsicsHardware(const std::string&,
                                                                    const std::string&,
                                                                    std::uint64_t, std::ostream&);
  IntrinsicsHardware() = default;
  HardwareConfig config_;
  TagBoardConfig board_;
  CalibrationRig rig_;
  std::string camera_name_;
  std::unique_ptr<World> world_;
  std::unique_ptr<RgbdCamera> camera_;
  std::size_t board_attachment_ = 0;
  std::function<void(IntrinsicsHardware&, double)> hand_;
};

/// Loads `hardware_path` (`world_path`, when given, replaces its world) and
/// its `calibration` rig, and opens the camera only (the arms and the
/// autopilot are not needed), printing one line on `out`.
/// @throws ConfigError for a 'replay' camera or a bad rig; HardwareError
/// "<file>: the camera did not open; nothing was recorded: camera (<backend>): ...".
std::unique_ptr<IntrinsicsHardware> OpenIntrinsicsHardware(const std::string& hardware_path,
                                                           const std::string& world_path,
                                                           std::uint64_t seed, std::ostream& out);

/// The board held by hand: checks the camera (a frame of its intrinsics'
/// size), prints what coverage is needed, writes the board to print
/// (DIR/board.svg, when `options.out_dir` is given), stops there with `dry_run`; else
/// grabs frames, detects the board in each and takes a frame as a sample when
/// the whole board is seen, still (no corner moved more than `calibration.still_px`
/// since the previous frame) and adds to the coverage (calib/coverage.h: a 3 x 3 grid of
/// the image, tilts about x and y beyond 20 deg), printing after each sample
/// what is still missing. Stops when the coverage is complete with at least
/// `options.poses` samples, on a line read from `in` (Enter or q) or on
/// Ctrl-C (the samples kept), then solves and writes what the planned run writes.
/// @throws HardwareError when the camera stops (the views kept); std::runtime_error
/// when fewer than 4 samples were taken.
void RunHandHeldIntrinsics(const CalibrateCommandOptions& options, IntrinsicsHardware& hw,
                           std::istream& in, std::ostream& out);

/// Without `options.hardware_path`: shows the board to the camera in `options.poses` planned views
/// (in the simulator a hand holds it 0.28-0.55 m in front of the camera, tilted 20-45 deg about
/// axes spread around the optical axis, its centre anywhere in the image), detects its corners,
/// rejects views with fewer than half its tags, solves with OpenCV's calibrateCamera
/// (calib/intrinsics_calibration.h), rejects views whose error stands out and solves again, and
/// writes DIR/views/NNN.png, DIR/views.yaml (the views, for --resolve), DIR/intrinsics.yaml,
/// DIR/camera.xml (ViSP's camera XML) and DIR/summary.json with the difference to the camera's own
/// (factory) intrinsics. With `options.hardware_path`: OpenIntrinsicsHardware and
/// RunHandHeldIntrinsics (Enter / q read from std::cin).
/// @throws ConfigError for bad options or hardware; std::runtime_error when
/// fewer than 4 views are usable (the views stay on disk).
void RunCalibrateIntrinsics(const CalibrateCommandOptions& options, std::ostream& out,
                            std::ostream& progress);

/// Whether `folder` holds an intrinsics run's views (views.yaml).
bool IsIntrinsicsFolder(const std::string& folder);

/// Solves again from `folder`/views.yaml and rewrites the results.
/// @throws ConfigError "<folder>/views.yaml: <key>: ..." for a malformed file.
void ResolveIntrinsics(const std::string& folder, std::ostream& out);

}  // namespace aerograsp
