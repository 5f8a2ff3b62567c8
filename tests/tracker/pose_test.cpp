// Pose estimation against rendered truth: single markers (both IPPE solutions),
// multi-marker objects by joint PnP, the camera in the world from the table's markers,
// the constant-velocity filter dropping an outlying fit, and the one-euro filter's
// jitter and lag.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "tests/tracker/tracker_test_support.hpp"
#include "tracker/detection/apriltag_detector.hpp"
#include "tracker/pose/marker_pose.hpp"
#include "tracker/pose/pose_filter.hpp"
#include "tracker/tracking/object_tracker.hpp"

namespace arphys::tracking {
namespace {

using geometry::rotation_distance_rad;
using geometry::translation_distance_m;
using testing::degrees;
using testing::detect_refined;
using testing::test_camera;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A 2x2 board of 5 cm tags on a 13 cm square (ids base..base+3), object frame at its centre.
ObjectModel board(const std::string& id, int base_id) {
  ObjectModel o;
  o.id = id;
  int k = 0;
  for (double y : {0.0325, -0.0325}) {
    for (double x : {-0.0325, 0.0325}) {
      o.markers.push_back({"tag36h11", base_id + k++, 0.05, geometry::translation_pose({x, y, 0})});
    }
  }
  return o;
}

std::vector<MarkerPlacement> place(const ObjectModel& o, const Pose& X_CO) {
  std::vector<MarkerPlacement> out;
  for (const auto& m : o.markers) out.push_back({m.family, m.id, m.size_m, X_CO * m.X_OM});
  return out;
}

TEST(MarkerPose, GivesBothSolutionsAndRefusesABadSize) {
  const CameraModel camera = test_camera();
  const MarkerPlacement m{"tag36h11", 1, 0.05, marker_pose_at(camera, 320, 240, 1.0, 0.05, 0.3, 0.2)};
  DetectedMarker d;
  d.corners_px = true_corners_px(camera, m);
  const MarkerPoseSolutions s = solve_marker_pose(d, 0.05, camera);
  ASSERT_EQ(s.count, 2);
  EXPECT_LT(translation_distance_m(s.X_CM[0], m.X_CM), 1e-6);
  EXPECT_LT(rotation_distance_rad(s.X_CM[0], m.X_CM), 1e-6);
  // Nearly frontal: the mirror solution tilts the other way.
  EXPECT_GT(rotation_distance_rad(s.X_CM[1], m.X_CM), 0.05);
  EXPECT_THROW(solve_marker_pose(d, 0.0, camera), std::invalid_argument);
  EXPECT_THROW(solve_marker_pose(d, std::nan(""), camera), std::invalid_argument);
}

// A 5 cm tag at 0.5 m, 0-40 degrees: with corners in the right pixel convention the
// median error is well under the 0.7 mm of the uncorrected convention.
TEST(MarkerPose, SingleTagAtHalfAMetre) {
  const CameraModel camera = test_camera();
  const cv::Mat background = clutter_background(640, 480, 5);
  AprilTagDetector detector;
  detector.set_param("decimate", "1");
  cv::RNG rng(3);
  std::vector<double> position_mm, rotation_deg;
  for (int i = 0; i < 30; ++i) {
    const double u = rng.uniform(260.0, 380.0), v = rng.uniform(200.0, 280.0), tilt = rng.uniform(0.35, 0.7);
    const double azimuth = rng.uniform(0.0, 6.28), spin = rng.uniform(0.0, 6.28);  // sequenced draws
    const MarkerPlacement m{"tag36h11", 2, 0.05, marker_pose_at(camera, u, v, 0.5, tilt, azimuth, spin)};
    ImageEffects effects;
    effects.noise_sigma = 2;
    effects.seed = i + 1;
    const auto found = detect_refined(detector, render_markers(camera, {m}, background, effects));
    ASSERT_EQ(found.size(), 1u);
    const MarkerPoseSolutions s = solve_marker_pose(found[0], 0.05, camera);
    position_mm.push_back(1e3 * translation_distance_m(s.X_CM[0], m.X_CM));
    rotation_deg.push_back(degrees(rotation_distance_rad(s.X_CM[0], m.X_CM)));
  }
  EXPECT_LT(median(position_mm), 0.4);
  EXPECT_LT(median(rotation_deg), 0.5);
}

// A 2x2 board seen at 0.5 m: the joint fit over 16 corners meets the target of 0.5 mm
// and 0.05 degrees, and never flips.
TEST(ObjectPose, JointFitOfAFourMarkerBoard) {
  const CameraModel camera = test_camera();
  TrackerModel model;
  model.objects.push_back(board("board", 20));
  const cv::Mat background = clutter_background(640, 480, 9);
  AprilTagDetector detector;
  detector.set_param("decimate", "1");
  cv::RNG rng(4);
  std::vector<double> position_mm, rotation_deg;
  for (int i = 0; i < 25; ++i) {
    ObjectTracker tracker(model, camera);  // independent views: no prediction helps
    const double u = rng.uniform(260.0, 380.0), v = rng.uniform(200.0, 280.0), tilt = rng.uniform(0.0, 0.6);
    const double azimuth = rng.uniform(0.0, 6.28), spin = rng.uniform(0.0, 6.28);  // sequenced draws
    const Pose X_CO = marker_pose_at(camera, u, v, 0.5, tilt, azimuth, spin);
    ImageEffects effects;
    effects.noise_sigma = 2;
    effects.seed = i + 1;
    const auto found = detect_refined(detector, render_markers(camera, place(model.objects[0], X_CO), background, effects));
    const TrackingResult r = tracker.update(found, 1000000);
    ASSERT_EQ(r.objects.size(), 1u);
    ASSERT_EQ(r.objects[0].status, TrackStatus::kTracked);
    EXPECT_EQ(r.objects[0].marker_ids.size(), 4u);
    position_mm.push_back(1e3 * translation_distance_m(r.objects[0].X_CO, X_CO));
    rotation_deg.push_back(degrees(rotation_distance_rad(r.objects[0].X_CO, X_CO)));
    EXPECT_LT(rotation_deg.back(), 1.0) << "flip in view " << i;
    // The reported 1-sigma figures are of the right size (within 10x of the error).
    EXPECT_GT(r.objects[0].position_sigma_m, 1e-6);
    EXPECT_LT(r.objects[0].position_sigma_m, 5e-3);
  }
  EXPECT_LT(median(position_mm), 0.5);
  EXPECT_LT(median(rotation_deg), 0.05);
}

// A webcam's barrel lens (k1 = -0.28): the 2x2 board near the image's corners, where the
// lens moves its corners by 10-15 px, is found to 1 mm, the pose solvers undoing the lens
// of the calibration; solved as if pinhole, the same pictures put it centimetres off.
TEST(ObjectPose, TheBoardThroughABarrelLensNearTheImageCorners) {
  CameraModel camera = test_camera();
  camera.distortion = (cv::Mat_<double>(1, 5) << -0.28, 0.09, 0.0005, -0.0003, 0.0);
  const CameraModel pinhole = test_camera();
  TrackerModel model;
  model.objects.push_back(board("board", 20));
  AprilTagDetector detector;
  detector.set_param("decimate", "1");
  cv::RNG rng(6);
  std::vector<double> position_mm, pinhole_mm;
  for (int i = 0; i < 12; ++i) {
    const double u = i % 2 ? 520.0 : 120.0, v = (i / 2) % 2 ? 370.0 : 110.0;
    const double tilt = rng.uniform(0.0, 0.5), azimuth = rng.uniform(0.0, 6.28), spin = rng.uniform(0.0, 6.28);
    const Pose X_CO = marker_pose_at(camera, u, v, 0.5, tilt, azimuth, spin);
    // (marker_pose_at aims through the pinhole pixel; the lens shows it elsewhere, still in view)
    ImageEffects effects;
    effects.noise_sigma = 2;
    effects.seed = i + 1;
    const auto found = detect_refined(detector, render_markers(camera, place(model.objects[0], X_CO), {}, effects));
    ObjectTracker tracker(model, camera), naive(model, pinhole);
    const TrackingResult r = tracker.update(found, 1000000), n = naive.update(found, 1000000);
    ASSERT_EQ(r.objects.size(), 1u);
    ASSERT_EQ(r.objects[0].status, TrackStatus::kTracked);
    ASSERT_EQ(n.objects.size(), 1u);
    position_mm.push_back(1e3 * translation_distance_m(r.objects[0].X_CO, X_CO));
    pinhole_mm.push_back(1e3 * translation_distance_m(n.objects[0].X_CO, X_CO));
  }
  std::printf("board near the corners through a barrel lens: median position error %.3f mm, %.1f mm solved as pinhole\n",
              median(position_mm), median(pinhole_mm));
  EXPECT_LT(median(position_mm), 1.0);
  EXPECT_GT(median(pinhole_mm), 5.0);
}

// A single frontal 5 cm tag at 1.5 m flips often when each frame is solved alone; in
// continuous tracking the prediction picks the right solution (target <= 0.5 %). Raw
// detector corners (no edge refinement, which alone removes most flips here) so that the
// ambiguity is really exercised.
TEST(ObjectPose, ContinuousTrackingResolvesSingleMarkerAmbiguity) {
  const CameraModel camera = test_camera();
  TrackerModel model;
  ObjectModel tag;
  tag.id = "tag";
  tag.markers.push_back({"tag36h11", 7, 0.05, Pose::Identity()});
  model.objects.push_back(tag);
  ObjectTracker tracked(model, camera);
  const cv::Mat background = clutter_background(640, 480, 13);
  AprilTagDetector detector;
  detector.set_param("decimate", "1");
  int flips_tracked = 0, flips_alone = 0, frames = 0;
  for (int i = 0; i < 90; ++i) {
    // Swings from 40 degrees through frontal to -40 and back, 30 frames per second.
    const double angle = 0.7 * std::cos(2 * M_PI * i / 90.0);
    const Pose X_CO = marker_pose_at(camera, 320 + 40 * std::sin(i * 0.05), 240, 1.5, angle, 0.4, 0.3);
    ImageEffects effects;
    effects.noise_sigma = 2;
    effects.seed = i + 1;
    const auto found = detector.detect(render_markers(camera, place(tag, X_CO), background, effects));
    const int64_t utime = 1000000 + i * 33333;
    const TrackingResult r = tracked.update(found, utime);
    ObjectTracker alone(model, camera);
    const TrackingResult a = alone.update(found, utime);
    if (r.objects[0].status != TrackStatus::kTracked) continue;
    ++frames;
    if (rotation_distance_rad(r.objects[0].X_CO, X_CO) > 10 * M_PI / 180) ++flips_tracked;
    if (rotation_distance_rad(a.objects[0].X_CO, X_CO) > 10 * M_PI / 180) ++flips_alone;
  }
  EXPECT_GE(frames, 88);
  // Raw corners of a 5 cm tag at 1.5 m swinging through frontal: 2-4 of 90 frames flip
  // when each is solved alone, depending on the compiler's rounding; the branch evidence
  // gives 0 (gcc) or 2 (clang): never worse, not always better, as the decisions near
  // frontal are that close. With the pipeline's edge refinement neither flips here, and
  // the tracked benchmark sequence has 0 of 300.
  EXPECT_GE(flips_alone, 2) << "the scene no longer exercises the ambiguity";
  EXPECT_LE(flips_tracked, flips_alone);
  EXPECT_LE(flips_tracked, 2);
}

// With the constant-velocity filter, one frame whose fit lands 8 cm off the board's
// path (a misfit, a single marker's flipped solution) is dropped: the object is reported
// PREDICTED there, on its path, and counted; the next frame is TRACKED again. Without the
// filter the jump goes out as a measurement.
TEST(ObjectPose, FilterDropsALoneOutlyingFitAsPredicted) {
  const CameraModel camera = test_camera();
  TrackerModel model;
  model.objects.push_back(board("board", 20));
  TrackerOptions options;
  options.filter.kind = PoseFilterKind::kConstantVelocity;
  ObjectTracker filtered(model, camera, options), raw(model, camera);
  const cv::Mat background = clutter_background(640, 480, 5);
  AprilTagDetector detector;
  detector.set_param("decimate", "1");
  int rejected = 0;
  for (int i = 0; i < 12; ++i) {
    // 0.3 m/s across the view at 0.6 m; frame 8 sees the board 8 cm further on.
    Pose X_CO = marker_pose_at(camera, 240, 240, 0.6, 0.3, 0.2, 0.1);
    X_CO.translation().x() += 0.01 * i + (i == 8 ? 0.08 : 0.0);
    const auto found = detect_refined(detector, render_markers(camera, place(model.objects[0], X_CO), background, {}));
    const int64_t utime = 1000000 + i * 33333;
    const TrackingResult r = filtered.update(found, utime);
    const TrackingResult u = raw.update(found, utime);
    rejected += r.rejected_poses;
    if (i == 8) {
      EXPECT_EQ(r.objects[0].status, TrackStatus::kPredicted);
      EXPECT_EQ(r.rejected_poses, 1);
      EXPECT_LT(translation_distance_m(r.objects[0].X_CO, X_CO), 0.08 + 2e-3);
      EXPECT_GT(translation_distance_m(r.objects[0].X_CO, X_CO), 0.08 - 2e-3);  // on the path, not at the jump
      EXPECT_LT(translation_distance_m(u.objects[0].X_CO, X_CO), 2e-3);
    } else {
      EXPECT_EQ(r.objects[0].status, TrackStatus::kTracked) << "frame " << i;
      if (i > 8) {
        EXPECT_LT(translation_distance_m(r.objects[0].X_CO, X_CO), 3e-3) << "frame " << i;
      }
    }
  }
  EXPECT_EQ(rejected, 1);
}

// The table's four corner markers give the camera in the world; a box seen in the same
// frame then has its pose in the world.
TEST(ObjectPose, CameraInTheWorldFromTheTable) {
  const CameraModel camera = test_camera();
  TrackerModel model;
  ObjectModel table;
  table.id = "table";
  table.defines_world = true;
  table.X_WO = geometry::translation_pose({0, 0, -0.02});
  int id = 0;
  for (double x : {-0.25, 0.25}) {
    for (double y : {-0.15, 0.15}) table.markers.push_back({"tag36h11", id++, 0.06, geometry::translation_pose({x, y, 0.02})});
  }
  model.objects.push_back(table);
  ObjectModel box = board("box", 30);
  model.objects.push_back(box);
  // Camera 0.8 m above the table, looking down at 40 degrees.
  Pose X_WC = Pose::Identity();
  X_WC.linear() = (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX())).toRotationMatrix();
  X_WC.translation() = Eigen::Vector3d(0, -0.55, 0.65);
  const Pose X_WB = geometry::translation_pose({0.05, 0.02, 0.001});
  std::vector<MarkerPlacement> placed;
  for (const auto& m : table.markers) placed.push_back({m.family, m.id, m.size_m, X_WC.inverse() * table.X_WO * m.X_OM});
  for (const auto& m : place(box, X_WC.inverse() * X_WB)) placed.push_back(m);
  ImageEffects effects;
  effects.noise_sigma = 2;
  AprilTagDetector detector;
  detector.set_param("decimate", "1");
  const auto found = detect_refined(detector, render_markers(camera, placed, clutter_background(640, 480, 2), effects));
  ASSERT_EQ(found.size(), 8u);
  ObjectTracker tracker(model, camera);
  const TrackingResult r = tracker.update(found, 1000000);
  ASSERT_TRUE(r.camera_world_valid);
  EXPECT_LT(translation_distance_m(r.X_WC, X_WC), 2e-3);
  EXPECT_LT(degrees(rotation_distance_rad(r.X_WC, X_WC)), 0.2);
  ASSERT_TRUE(r.objects[1].world_valid);
  EXPECT_LT(translation_distance_m(r.objects[1].X_WO, X_WB), 2e-3);
  EXPECT_EQ(r.objects[0].status, TrackStatus::kTracked);
  EXPECT_EQ(r.unknown_markers, 0);
}

// One-euro filter: a still pose's jitter shrinks several-fold, and on a 0.2 m/s ramp
// the lag stays under 40 ms (its cutoff rises with speed).
TEST(PoseFilter, CutsJitterWithBoundedLag) {
  OneEuroPoseFilter filter;
  cv::RNG rng(5);
  double raw_sq = 0, filtered_sq = 0;
  for (int i = 0; i < 300; ++i) {
    const double x = rng.gaussian(1e-3), y = rng.gaussian(1e-3), z = 0.5 + rng.gaussian(1e-3);  // sequenced
    Pose X = geometry::translation_pose({x, y, z});
    const Pose Y = filter.filter(X, i / 30.0);
    if (i < 30) continue;
    raw_sq += (X.translation() - Eigen::Vector3d(0, 0, 0.5)).squaredNorm();
    filtered_sq += (Y.translation() - Eigen::Vector3d(0, 0, 0.5)).squaredNorm();
  }
  EXPECT_LT(std::sqrt(filtered_sq / raw_sq), 0.5);

  filter.reset();
  double lag_s = 0;
  for (int i = 0; i < 90; ++i) {
    const double t = i / 30.0, x = 0.2 * t;
    const Pose Y = filter.filter(geometry::translation_pose({x, 0, 0.5}), t);
    lag_s = (x - Y.translation().x()) / 0.2;
  }
  EXPECT_GT(lag_s, 0.0);
  EXPECT_LT(lag_s, 0.04);
}

}  // namespace
}  // namespace arphys::tracking
