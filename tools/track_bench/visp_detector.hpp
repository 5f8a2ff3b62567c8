#pragma once
// The peer: ViSP 3.5's AprilTag detector (vpDetectorAprilTag, Debian's libvisp-detection-dev)
// behind the tracker's MarkerDetector interface, so the benchmark runs it on the same frames
// and through the same pose pipeline as ours. Benchmark only: the product does not use it.
#include <memory>

#include "tracker/detection/marker_detector.hpp"

namespace arphys::bench {

// tag36h11; `quad_decimate` as apriltag's decimate. The image's copy into ViSP's image type
// is part of each detect(), as it is for a ViSP user.
std::unique_ptr<tracking::MarkerDetector> make_visp_apriltag(double quad_decimate);

}  // namespace arphys::bench
