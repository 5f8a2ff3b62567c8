// arphys-track-bench: the tracker's speed and accuracy on rendered frames with exact
// ground truth, every detector configuration on the same frames, ViSP's AprilTag
// detector (the peer) among them.
//
//   sweep:    single markers over distance, view angle and size (independent pictures):
//             detection rate, corner error, pose error, flips.
//   sequence: a 640x480 video of a moving 2x2 board and a moving single marker, run in
//             order (prediction allowed): ms per frame, recall against decimation 1,
//             pose errors and flips in continuous tracking: the speed/accuracy frontier.
//   photos:   the apriltag repository's real photos (photo_pass.hpp): reference detections
//             found, corner offsets, single-marker fit residuals, ms per photo.
// Writes track_sweep.csv, track_effects.csv, track_sequence.csv, track_frames.csv and
// track_photos.csv to --out.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "tools/track_bench/photo_pass.hpp"
#include "tools/track_bench/visp_detector.hpp"
#include "tracker/detection/edge_refinement.hpp"
#include "tracker/detection/marker_detector.hpp"
#include "tracker/pose/marker_pose.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"
#include "tracker/tracking/object_tracker.hpp"

namespace {

using namespace arphys;
using namespace arphys::tracking;

struct Config {
  std::string name;
  DetectorSpec spec;
  bool refine = true;
  bool video_only = false;  // needs frame-to-frame prediction
};

std::vector<Config> configs() {
  return {
      {"apriltag_d1", {"apriltag", {"tag36h11"}, {{"decimate", "1"}}}, true},
      {"apriltag_d2", {"apriltag", {"tag36h11"}, {{"decimate", "2"}}}, true},
      {"apriltag_d2_raw", {"apriltag", {"tag36h11"}, {{"decimate", "2"}}}, false},
      {"apriltag_d4", {"apriltag", {"tag36h11"}, {{"decimate", "4"}}}, true},
      {"apriltag_cand", {"apriltag", {"tag36h11"}, {{"candidate_search", "1"}}}, true},
      {"apriltag_roi", {"apriltag", {"tag36h11"}, {{"roi_tracking", "1"}}}, true, true},
      {"aruco_subpix", {"aruco", {"tag36h11"}, {{"corner_refinement", "subpix"}}}, true},
      {"aruco_subpix_raw", {"aruco", {"tag36h11"}, {{"corner_refinement", "subpix"}}}, false},
      {"aruco_t20", {"aruco", {"tag36h11"}, {{"threshold_step", "20"}}}, true},
      {"aruco_roi", {"aruco", {"tag36h11"}, {{"roi_tracking", "1"}}}, true, true},
      {"aruco_roi_t20", {"aruco", {"tag36h11"}, {{"roi_tracking", "1"}, {"threshold_step", "20"}}}, true, true},
      {"aruco_roi_t20_c4",
       {"aruco", {"tag36h11"}, {{"roi_tracking", "1"}, {"threshold_step", "20"}, {"coarse_every", "4"}}},
       true,
       true},
      // The peer, as a ViSP user gets it (its corners without our edge refinement).
      {"visp_d1", {"visp", {"tag36h11"}, {{"decimate", "1"}}}, false},
      {"visp_d2", {"visp", {"tag36h11"}, {{"decimate", "2"}}}, false},
  };
}

// The configurations that work on independent pictures (the sweeps).
std::vector<Config> picture_configs() {
  std::vector<Config> list;
  for (const auto& c : configs()) {
    if (!c.video_only) list.push_back(c);
  }
  return list;
}

std::unique_ptr<MarkerDetector> detector_for(const Config& c) { return bench::make_bench_detector(c.spec); }

std::vector<std::unique_ptr<MarkerDetector>> make_detectors(const std::vector<Config>& list) {
  std::vector<std::unique_ptr<MarkerDetector>> detectors;
  for (const auto& c : list) detectors.push_back(detector_for(c));
  return detectors;
}

double degrees(double rad) { return rad * 180.0 / M_PI; }

using bench::percentile;

CameraModel bench_camera() {
  CameraModel camera;
  camera.width_px = 640;
  camera.height_px = 480;
  camera.K = cv::Matx33d(600, 0, 319.5, 0, 600, 239.5, 0, 0, 1);
  return camera;
}

std::vector<DetectedMarker> run_detector(MarkerDetector& detector, const cv::Mat& image, bool refine, double* ms) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<DetectedMarker> found = detector.detect(image);
  if (refine) {
    for (auto& m : found) refine_corners_on_edges(image, m);
  }
  *ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return found;
}

void sweep(const std::string& out_dir, int trials, uint64_t seed) {
  const CameraModel camera = bench_camera();
  const cv::Mat background = clutter_background(640, 480, 101);
  const std::vector<Config> list = picture_configs();
  const auto detectors = make_detectors(list);
  std::ofstream csv(out_dir + "/track_sweep.csv");
  csv << "config,size_m,distance_m,angle_deg,trial,ms,detected,corner_rms_px,position_error_mm,rotation_error_deg,"
         "flip\n";
  cv::RNG rng(seed);
  const std::vector<double> sizes{0.05, 0.10}, distances{0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0};
  const int total = static_cast<int>(sizes.size() * distances.size()) * 8 * trials;
  int done = 0;
  for (double size : sizes) {
    for (double distance : distances) {
      for (int angle_deg = 0; angle_deg <= 70; angle_deg += 10) {
        for (int trial = 0; trial < trials; ++trial, ++done) {
          if (done % 100 == 0) std::fprintf(stderr, "sweep: %d / %d views\n", done, total);
          MarkerPlacement m{"tag36h11", static_cast<int>(rng.uniform(0, 20)), size, Pose::Identity()};
          // Keep the whole marker and its quiet zone 4 px inside the frame.
          bool fits = false;
          for (double shrink = 1.0; shrink > 0.01 && !fits; shrink *= 0.7) {
            // Draws sequenced: argument order differs between compilers.
            const double du = rng.uniform(-120.0, 120.0), dv = rng.uniform(-90.0, 90.0);
            const double azimuth = rng.uniform(0.0, 2 * M_PI), spin = rng.uniform(0.0, 2 * M_PI);
            m.X_CM = marker_pose_at(camera, 319.5 + shrink * du, 239.5 + shrink * dv, distance, angle_deg * M_PI / 180,
                                    azimuth, spin);
            MarkerPlacement outer = m;
            outer.size_m = size * 10 / 8;
            fits = true;
            for (const auto& c : true_corners_px(camera, outer)) {
              fits = fits && c.x() > 4 && c.y() > 4 && c.x() < 635 && c.y() < 475;
            }
          }
          if (!fits) continue;
          ImageEffects effects;
          effects.noise_sigma = 2;
          effects.seed = static_cast<uint32_t>(done + 1);
          const cv::Mat image = render_markers(camera, {m}, background, effects);
          const auto truth = true_corners_px(camera, m);
          for (size_t c = 0; c < list.size(); ++c) {
            double ms = 0;
            const auto found = run_detector(*detectors[c], image, list[c].refine, &ms);
            const DetectedMarker* d = nullptr;
            for (const auto& f : found) {
              if (f.id == m.id) d = &f;
            }
            csv << list[c].name << "," << size << "," << distance << "," << angle_deg << "," << trial << "," << ms
                << "," << (d ? 1 : 0);
            if (!d) {
              csv << ",,,,\n";
              continue;
            }
            double sq = 0;
            for (int k = 0; k < 4; ++k) sq += (d->corners_px[k] - truth[k]).squaredNorm();
            const MarkerPoseSolutions s = solve_marker_pose(*d, size, camera);
            const double rot = degrees(geometry::rotation_distance_rad(s.X_CM[0], m.X_CM));
            csv << "," << std::sqrt(sq / 4) << "," << 1e3 * geometry::translation_distance_m(s.X_CM[0], m.X_CM) << ","
                << rot << "," << (rot > 10 ? 1 : 0) << "\n";
          }
        }
      }
    }
  }
}

// Image degradations at a fixed view (10 cm tag, 1 m, 30 degrees): noise and motion blur.
void effects_sweep(const std::string& out_dir, int trials, uint64_t seed) {
  const CameraModel camera = bench_camera();
  const cv::Mat background = clutter_background(640, 480, 303);
  const std::vector<Config> list = picture_configs();
  const auto detectors = make_detectors(list);
  std::ofstream csv(out_dir + "/track_effects.csv");
  csv << "config,noise_sigma,blur_px,trial,detected,corner_rms_px,position_error_mm,rotation_error_deg\n";
  cv::RNG rng(seed + 17);
  const std::vector<std::pair<double, double>> conditions{{0, 0},  {2, 0},  {5, 0},  {10, 0}, {20, 0},
                                                          {2, 5},  {2, 10}, {2, 15}, {2, 20}};
  std::fprintf(stderr, "effects: %zu conditions x %d trials\n", conditions.size(), trials * 4);
  for (const auto& [noise, blur] : conditions) {
    for (int trial = 0; trial < trials * 4; ++trial) {
      const int id = rng.uniform(0, 20);
      const double u = rng.uniform(250.0, 390.0), v = rng.uniform(190.0, 290.0);
      const double azimuth = rng.uniform(0.0, 2 * M_PI), spin = rng.uniform(0.0, 2 * M_PI);
      const MarkerPlacement m{"tag36h11", id, 0.10, marker_pose_at(camera, u, v, 1.0, 30 * M_PI / 180, azimuth, spin)};
      ImageEffects effects;
      effects.noise_sigma = noise;
      effects.blur_length_px = blur;
      effects.blur_angle_rad = rng.uniform(0.0, M_PI);
      effects.seed = static_cast<uint32_t>(trial + 1000 * blur + 7 * noise + 1);
      const cv::Mat image = render_markers(camera, {m}, background, effects);
      const auto truth = true_corners_px(camera, m);
      for (size_t c = 0; c < list.size(); ++c) {
        double ms = 0;
        const auto found = run_detector(*detectors[c], image, list[c].refine, &ms);
        const DetectedMarker* d = nullptr;
        for (const auto& f : found) {
          if (f.id == m.id) d = &f;
        }
        csv << list[c].name << "," << noise << "," << blur << "," << trial << "," << (d ? 1 : 0);
        if (!d) {
          csv << ",,,\n";
          continue;
        }
        double sq = 0;
        for (int k = 0; k < 4; ++k) sq += (d->corners_px[k] - truth[k]).squaredNorm();
        const MarkerPoseSolutions s = solve_marker_pose(*d, m.size_m, camera);
        csv << "," << std::sqrt(sq / 4) << "," << 1e3 * geometry::translation_distance_m(s.X_CM[0], m.X_CM) << ","
            << degrees(geometry::rotation_distance_rad(s.X_CM[0], m.X_CM)) << "\n";
      }
    }
  }
}

struct SequenceTruth {
  Pose X_C_board;
  Pose X_C_tag;
};

void sequence(const std::string& out_dir, int frames, int repeats, const std::vector<std::string>& only) {
  const CameraModel camera = bench_camera();
  const cv::Mat background = clutter_background(640, 480, 202);
  TrackerModel model;
  ObjectModel board;
  board.id = "board";
  int k = 0;
  for (double y : {0.0325, -0.0325}) {
    for (double x : {-0.0325, 0.0325}) board.markers.push_back({"tag36h11", 20 + k++, 0.05, geometry::translation_pose({x, y, 0})});
  }
  ObjectModel tag;
  tag.id = "tag";
  tag.markers.push_back({"tag36h11", 7, 0.05, Pose::Identity()});
  model.objects = {board, tag};

  // Render once; every configuration sees the same frames.
  std::fprintf(stderr, "sequence: rendering %d frames\n", frames);
  std::vector<cv::Mat> images;
  std::vector<SequenceTruth> truth;
  for (int i = 0; i < frames; ++i) {
    const double t = i / 30.0;
    SequenceTruth gt;
    // The board circles at 0.5 m, the tag swings through frontal at 0.8 m.
    gt.X_C_board = marker_pose_at(camera, 220 + 60 * std::cos(0.8 * t), 240 + 60 * std::sin(0.8 * t), 0.5,
                                  0.35 + 0.25 * std::sin(1.3 * t), 0.5 * t, 0.2 * t);
    gt.X_C_tag = marker_pose_at(camera, 470 + 40 * std::sin(0.6 * t), 200 + 50 * std::cos(0.5 * t), 0.8,
                                0.6 * std::cos(2 * M_PI * t / 4.0), 0.4, 0.3);
    std::vector<MarkerPlacement> placed;
    for (const auto& m : board.markers) placed.push_back({m.family, m.id, m.size_m, gt.X_C_board * m.X_OM});
    placed.push_back({"tag36h11", 7, 0.05, gt.X_C_tag});
    ImageEffects effects;
    effects.noise_sigma = 2;
    effects.seed = static_cast<uint32_t>(i + 1);
    images.push_back(render_markers(camera, placed, background, effects));
    truth.push_back(gt);
  }

  std::ofstream csv(out_dir + "/track_sequence.csv");
  csv << "config,median_ms,p90_ms,recall_vs_d1,board_position_mm,board_rotation_deg,board_flips,tag_position_mm,"
         "tag_rotation_deg,tag_flips,tag_frames\n";
  std::ofstream frames_csv(out_dir + "/track_frames.csv");
  frames_csv << "config,frame,ms,markers,board_rotation_deg,tag_rotation_deg\n";
  std::map<int, std::vector<int>> d1_found;  // frame -> ids found by decimation 1
  std::printf("\n%-18s %9s %8s %10s %11s %11s %7s %11s %11s %9s\n", "config", "median_ms", "p90_ms", "recall_d1",
              "board_mm", "board_deg", "b_flips", "tag_mm", "tag_deg", "t_flips");
  for (const auto& config : configs()) {
    // apriltag_d1 always runs: it is the reference the others' recall is counted against.
    if (!only.empty() && config.name != "apriltag_d1" &&
        std::find(only.begin(), only.end(), config.name) == only.end()) {
      continue;
    }
    std::vector<double> ms_all, board_mm, board_deg, tag_mm, tag_deg;
    int board_flips = 0, tag_flips = 0, tag_frames = 0, recalled = 0, reference = 0;
    for (int rep = 0; rep < repeats; ++rep) {
      auto detector = detector_for(config);
      ObjectTracker tracker(model, camera);
      for (int i = 0; i < frames; ++i) {
        double ms = 0;
        const auto found = run_detector(*detector, images[i], config.refine, &ms);
        ms_all.push_back(ms);
        if (rep > 0) continue;  // accuracy from the first pass; later passes only time
        std::vector<int> ids;
        for (const auto& f : found) ids.push_back(f.id);
        if (config.name == "apriltag_d1") d1_found[i] = ids;
        for (int id : d1_found[i]) {
          ++reference;
          recalled += std::count(ids.begin(), ids.end(), id) > 0 ? 1 : 0;
        }
        const TrackingResult r = tracker.update(found, 1'000'000 + static_cast<int64_t>(i) * 33'333);
        double b = NAN, tg = NAN;
        if (r.objects[0].status == TrackStatus::kTracked) {
          board_mm.push_back(1e3 * geometry::translation_distance_m(r.objects[0].X_CO, truth[i].X_C_board));
          b = degrees(geometry::rotation_distance_rad(r.objects[0].X_CO, truth[i].X_C_board));
          board_deg.push_back(b);
          board_flips += b > 10 ? 1 : 0;
        }
        if (r.objects[1].status == TrackStatus::kTracked) {
          ++tag_frames;
          tag_mm.push_back(1e3 * geometry::translation_distance_m(r.objects[1].X_CO, truth[i].X_C_tag));
          tg = degrees(geometry::rotation_distance_rad(r.objects[1].X_CO, truth[i].X_C_tag));
          tag_deg.push_back(tg);
          tag_flips += tg > 10 ? 1 : 0;
        }
        frames_csv << config.name << "," << i << "," << ms << "," << found.size() << "," << b << "," << tg << "\n";
      }
    }
    const double recall = reference ? static_cast<double>(recalled) / reference : NAN;
    csv << config.name << "," << percentile(ms_all, 0.5) << "," << percentile(ms_all, 0.9) << "," << recall << ","
        << percentile(board_mm, 0.5) << "," << percentile(board_deg, 0.5) << "," << board_flips << ","
        << percentile(tag_mm, 0.5) << "," << percentile(tag_deg, 0.5) << "," << tag_flips << "," << tag_frames << "\n";
    std::printf("%-18s %9.2f %8.2f %10.3f %11.3f %11.4f %7d %11.3f %11.3f %5d/%-4d\n", config.name.c_str(),
                percentile(ms_all, 0.5), percentile(ms_all, 0.9), recall, percentile(board_mm, 0.5),
                percentile(board_deg, 0.5), board_flips, percentile(tag_mm, 0.5), percentile(tag_deg, 0.5), tag_flips,
                tag_frames);
    std::fflush(stdout);
  }
}

// The real photos, with the reference's own configuration first (apriltag at decimation 1,
// corners unrefined) and each detector with and without the edge refinement.
void photos(const std::string& out_dir, const std::string& folder, const std::string& camera_yaml, int repeats) {
  std::vector<bench::PhotoConfig> list{
      {"apriltag_d1_reference", {"apriltag", {"tag36h11"}, {{"decimate", "1"}, {"refine_edges", "0"}}}, false},
      {"apriltag_d1_raw", {"apriltag", {"tag36h11"}, {{"decimate", "1"}}}, false}};
  for (const auto& c : picture_configs())
    if (c.name != "apriltag_d4" && c.name != "aruco_t20") list.push_back({c.name, c.spec, c.refine});
  std::fprintf(stderr, "photos: %zu configurations on %s\n", list.size(), folder.c_str());
  const auto figures = bench::photo_pass(list, folder, camera_yaml, repeats);
  std::ofstream csv(out_dir + "/track_photos.csv");
  csv << "config,references,found,extra,corner_offset_median_px,corner_offset_p90_px,reprojection_median_px,"
         "reprojection_p90_px,median_ms\n";
  std::printf("\n%-18s %6s %6s %14s %14s %8s\n", "config", "found", "extra", "offset_px", "reproj_px", "ms");
  for (const auto& f : figures) {
    csv << f.config << "," << f.references << "," << f.found << "," << f.extra << "," << f.corner_offset_median_px
        << "," << f.corner_offset_p90_px << "," << f.reprojection_median_px << "," << f.reprojection_p90_px << ","
        << f.median_ms << "\n";
    std::printf("%-18s %3d/%-2d %6d %6.3f (%5.3f) %6.3f (%5.3f) %8.2f\n", f.config.c_str(), f.found, f.references,
                f.extra, f.corner_offset_median_px, f.corner_offset_p90_px, f.reprojection_median_px,
                f.reprojection_p90_px, f.median_ms);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys tracker benchmark: detectors x distance, angle, size (sweep) and a tracked video (sequence),\n"
               "on rendered 640x480 frames with exact ground truth. Writes CSV to --out."};
  std::string out = ".";
  int trials = 5, frames = 300, repeats = 3;
  uint64_t seed = 1;
  bool quick = false, no_sweep = false;
  std::string photo_folder = std::string(ARPHYS_SOURCE_DIR) + "/tests/data/apriltag_photos";
  std::string photo_camera = std::string(ARPHYS_SOURCE_DIR) + "/tests/data/nominal_camera_799x533.yaml";
  std::vector<std::string> only;
  app.add_option("--out", out, "output directory")->capture_default_str();
  app.add_option("--trials", trials, "random views per sweep cell")->capture_default_str();
  app.add_option("--frames", frames, "frames of the sequence (30 per second)")->capture_default_str();
  app.add_option("--repeats", repeats, "timing passes over the sequence")->capture_default_str();
  app.add_option("--seed", seed, "random seed of the sweep")->capture_default_str();
  app.add_flag("--quick", quick, "2 trials, 90 frames, 1 pass (a smoke run)");
  app.add_flag("--no-sweep", no_sweep, "only the sequence (and the photos)");
  app.add_option("--photos", photo_folder, "real photos with reference detections (NAME.jpg, NAME.txt)")
      ->capture_default_str();
  app.add_option("--photos-camera", photo_camera, "the photos' camera file")->capture_default_str();
  std::vector<std::string> names;
  for (const auto& c : configs()) names.push_back(c.name);
  app.add_option("--config", only, "sequence: only these configurations (and apriltag_d1, the recall reference)")
      ->check(CLI::IsMember(names));
  CLI11_PARSE(app, argc, argv);
  cv::setNumThreads(1);  // one thread for every detector: the figures compare algorithms
  if (quick) {
    trials = 2;
    frames = 90;
    repeats = 1;
  }
  if (!no_sweep) {
    sweep(out, trials, seed);
    effects_sweep(out, trials, seed);
  }
  sequence(out, frames, repeats, only);
  photos(out, photo_folder, photo_camera, repeats);
  return 0;
}
