#pragma once
// The evaluation's stability scenario: a tracked real box (the scene's "box") pushes a
// virtual bunny resting on the table, as in the paper's application 2, with the
// tracking made worse on purpose. The box truly moves at push_speed_m_s along +x; the
// simulator sees it only through frames at frame_rate_hz with Gaussian pose noise, lost
// frames and pose flips, and drives it one of three ways:
//   kScrew:          arphys (TrackingDriver, delay policy): screw motion between poses;
//   kScrewFiltered:  the same, after the tracker's constant-velocity pose filter;
//   kTeleport:       what a naive coupling does: the body jumps to each pose, velocity 0
//                    (no consistency step: overlap is left to depenetration).
// The outcome is what the bunny did: peak speed against the pusher's, deepest overlap,
// highest hop above its rest height, and whether anything went non-finite.
#include <string>

#include "configs/loader/scene_config.hpp"

namespace arphys::eval {

enum class Drive { kScrew, kScrewFiltered, kTeleport };
const char* to_string(Drive drive);

struct PushScenario {
  double frame_rate_hz = 30;
  double noise_position_m = 0;   // standard deviation per axis
  double noise_rotation_deg = 0; // standard deviation of the rotation angle per axis
  Drive drive = Drive::kScrew;
  double lost_from_s = -1;       // frames captured in [lost_from_s, lost_from_s + lost_for_s) are LOST
  double lost_for_s = 0;
  double flip_at_s = -1;         // the frame nearest this time reports the box flipped (IPPE's other solution)
  double flip_angle_deg = 40;    // tilt of the flipped pose about the camera's view, as an ambiguity looks
  double push_speed_m_s = 0.25;
  double duration_s = 3.0;
  unsigned seed = 1;
};

struct PushOutcome {
  double peak_speed_ratio = 0;  // bunny's peak centre-of-mass speed over the pusher's
  double max_overlap_mm = 0;    // deepest penetration the world reported
  double max_rise_mm = 0;       // highest the bunny's centre of mass rose above its rest height
  double pushed_m = 0;          // how far the bunny moved along x
  double ms_per_step = 0;
  bool non_finite = false;
};

// scene: bunny_box_table (its table, box and bunny objects are used; spawns ignored).
PushOutcome run_push(const config::SceneConfig& scene, const PushScenario& scenario);

}  // namespace arphys::eval
