#pragma once
// The peer: ViSP 3.5's AprilTag detector (vpDetectorAprilTag, Debian's libvisp-detection-dev)
// behind the tracker's MarkerDetector interface, so the benchmark runs it on the same frames
// and through the same pose pipeline as ours. Benchmark only: the product does not use it.
#include <memory>
#include <vector>

#include "tracker/detection/marker_detector.hpp"

namespace arphys::bench {

// tag36h11; `quad_decimate` as apriltag's decimate. The image's copy into ViSP's image type
// is part of each detect(), as it is for a ViSP user.
std::unique_ptr<tracking::MarkerDetector> make_visp_apriltag(double quad_decimate);

// The benchmark's detector for a spec: ViSP's for implementation "visp" (its first parameter
// the decimation), the tracker's own (make_detector) for any other.
std::unique_ptr<tracking::MarkerDetector> make_bench_detector(const tracking::DetectorSpec& spec);

// The value at fraction p (0..1) of the sorted values, NaN for none.
double percentile(std::vector<double> values, double p);

}  // namespace arphys::bench
