// The pipeline's behaviour at its edges: lost tracks, unknown markers, frames of the
// wrong size or format, and swapping the detector between frames.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "tests/tracker/tracker_test_support.hpp"
#include "tracker/pipeline/tracker_pipeline.hpp"

namespace arphys::tracking {
namespace {

using testing::test_camera;

struct Scene {
  TrackerModel model;
  Pose X_CO = Pose::Identity();
  Scene() {
    ObjectModel box;
    box.id = "box";
    box.markers.push_back({"tag36h11", 3, 0.08, Pose::Identity()});
    model.objects.push_back(box);
    X_CO = marker_pose_at(test_camera(), 320, 240, 0.6, 0.5, 0.2, 0.3);
  }
  Frame frame(bool with_marker, int64_t utime, int extra_id = -1) const {
    std::vector<MarkerPlacement> placed;
    if (with_marker) placed.push_back({"tag36h11", 3, 0.08, X_CO});
    if (extra_id >= 0) placed.push_back({"tag36h11", extra_id, 0.08, marker_pose_at(test_camera(), 120, 120, 0.6, 0.3, 1, 0)});
    Frame f;
    f.image = render_markers(test_camera(), placed, clutter_background(640, 480, 1));
    f.capture_utime = utime;
    return f;
  }
};

TrackerPipeline make_pipeline(const Scene& scene, TrackerOptions options = {}) {
  return TrackerPipeline(make_detector({"apriltag", {"tag36h11"}, {}}), ObjectTracker(scene.model, test_camera(), options));
}

// Seen: TRACKED. Unseen: PREDICTED for predict_s, then LOST with its last pose and the
// time it was last seen; never a stale pose presented as fresh. Seen again: TRACKED.
TEST(TrackerPipeline, LostTrackGoesPredictedThenLost) {
  const Scene scene;
  TrackerOptions options;
  options.predict_s = 0.1;
  TrackerPipeline pipeline = make_pipeline(scene, options);
  const int64_t t0 = 1'000'000'000;
  auto r = pipeline.process(scene.frame(true, t0));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->result.objects[0].status, TrackStatus::kTracked);
  EXPECT_LT(geometry::translation_distance_m(r->result.objects[0].X_CO, scene.X_CO), 1e-3);
  r = pipeline.process(scene.frame(false, t0 + 50'000));
  EXPECT_EQ(r->result.objects[0].status, TrackStatus::kPredicted);
  EXPECT_EQ(r->result.objects[0].last_seen_utime, t0);
  r = pipeline.process(scene.frame(false, t0 + 150'000));
  EXPECT_EQ(r->result.objects[0].status, TrackStatus::kLost);
  EXPECT_EQ(r->result.objects[0].last_seen_utime, t0);
  EXPECT_LT(geometry::translation_distance_m(r->result.objects[0].X_CO, scene.X_CO), 1e-3);
  r = pipeline.process(scene.frame(true, t0 + 200'000));
  EXPECT_EQ(r->result.objects[0].status, TrackStatus::kTracked);
  EXPECT_EQ(r->result.objects[0].last_seen_utime, t0 + 200'000);
}

TEST(TrackerPipeline, NeverSeenObjectIsLostAndUnknownMarkersAreCounted) {
  const Scene scene;
  TrackerPipeline pipeline = make_pipeline(scene);
  const auto r = pipeline.process(scene.frame(false, 1000, 42));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->result.objects[0].status, TrackStatus::kLost);
  EXPECT_EQ(r->result.objects[0].last_seen_utime, 0);
  ASSERT_EQ(r->result.markers.size(), 1u);
  EXPECT_TRUE(r->result.markers[0].owner.empty());
  EXPECT_FALSE(r->result.markers[0].has_pose);  // no size known for it
  EXPECT_EQ(pipeline.counters().unknown_markers, 1);
}

TEST(TrackerPipeline, FramesOfTheWrongSizeOrFormatAreCountedAndSkipped) {
  const Scene scene;
  TrackerPipeline pipeline = make_pipeline(scene);
  Frame small;
  small.image = cv::Mat(240, 320, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(pipeline.process(small));
  Frame floating;
  floating.image = cv::Mat(480, 640, CV_32FC1, cv::Scalar(0.5));
  EXPECT_FALSE(pipeline.process(floating));
  Frame colour;
  cv::cvtColor(scene.frame(true, 1000).image, colour.image, cv::COLOR_GRAY2BGR);
  const auto r = pipeline.process(colour);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->result.objects[0].status, TrackStatus::kTracked);
  EXPECT_EQ(pipeline.counters().wrong_size, 1);
  EXPECT_EQ(pipeline.counters().wrong_format, 1);
  EXPECT_EQ(pipeline.counters().frames, 1);
}

// Swapping apriltag for ArUco between frames keeps the track (same corners, same
// object pose within a millimetre); a bad request leaves the running detector alone.
TEST(TrackerPipeline, DetectorSwapKeepsTracking) {
  const Scene scene;
  TrackerPipeline pipeline = make_pipeline(scene);
  auto r = pipeline.process(scene.frame(true, 1000));
  ASSERT_EQ(r->result.objects[0].status, TrackStatus::kTracked);
  EXPECT_EQ(pipeline.detector().implementation(), "apriltag");
  pipeline.switch_detector({"aruco", {}, {{"corner_refinement", "subpix"}}});
  EXPECT_EQ(pipeline.detector().implementation(), "aruco");
  r = pipeline.process(scene.frame(true, 34000));
  ASSERT_EQ(r->result.objects[0].status, TrackStatus::kTracked);
  EXPECT_NE(r->implementation.find("aruco"), std::string::npos);
  EXPECT_LT(geometry::translation_distance_m(r->result.objects[0].X_CO, scene.X_CO), 1e-3);
  EXPECT_THROW(pipeline.switch_detector({"aruco", {}, {{"decimate", "2"}}}), std::invalid_argument);
  EXPECT_THROW(pipeline.switch_detector({"nonsense", {}, {}}), std::invalid_argument);
  EXPECT_EQ(pipeline.detector().implementation(), "aruco");
  EXPECT_EQ(pipeline.counters().detector_switches, 1);
}

}  // namespace
}  // namespace arphys::tracking
