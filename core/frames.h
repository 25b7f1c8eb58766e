// The frame glossary of aerograsp. Every pose in the code base is named `aMb`:
// frame b expressed in frame a (ViSP convention), so compositions chain with
// cancelling inner letters: blMg = blMd * dMc * cMo * oMg.
//
//   w   world, NED (x north, y east, z down), as PX4's local frame
//   d   drone body, FRD (x forward, y right, z down), origin at the body centre
//   c   camera optical frame (z along the view, x right, y down in the image)
//   bl  left arm base, br right arm base (the URDF `base_link` of each arm)
//   el  left end effector, er right end effector: the tool point between the
//       fingers; z is the approach axis, x the direction the fingers close along
//   o   object model frame (the frame its mesh is written in)
//   g   grasp frame: where an end effector must be to grasp (same axes as e)
//   t   tag board frame
//
// Units are SI (m, s, rad) unless a name carries its unit (`timeout_ms`,
// `fov_deg`, `raw_ticks`). Quaternions are stored (w, x, y, z) wherever they
// cross an API or a file; the order is restated at each such place.
#pragma once

namespace aerograsp {

/// Names of the frames as they appear in configuration files, logs and reports.
namespace frame {
inline constexpr const char* kWorld = "w";
inline constexpr const char* kBody = "d";
inline constexpr const char* kCamera = "c";
inline constexpr const char* kLeftBase = "bl";
inline constexpr const char* kRightBase = "br";
inline constexpr const char* kLeftEffector = "el";
inline constexpr const char* kRightEffector = "er";
inline constexpr const char* kObject = "o";
inline constexpr const char* kGrasp = "g";
inline constexpr const char* kTagBoard = "t";
}  // namespace frame

}  // namespace aerograsp
