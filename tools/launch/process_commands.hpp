#pragma once
// The command line of each process a launch starts, in start order: the recorder,
// simulator, renderer and tracker, then the frame source (started last, once the others
// listen). Pure: no process is started here.
#include <string>
#include <vector>

#include "configs/loader/camera_script.hpp"
#include "configs/loader/scene_config.hpp"
#include "tools/launch/launch_options.hpp"

namespace arphys::launch {

struct ProcessCommand {
  std::string name;  // recorder, simulator, renderer, tracker, camera
  std::vector<std::string> args;
};

// `script`: the synthetic camera's (nullptr for a real source); `state_file`: where the
// simulator keeps its last world state, so that a restarted one resumes it. With a replay
// log, arphys-replay takes the camera's place (and the tracker's too, replaying poses).
std::vector<ProcessCommand> process_commands(const LaunchOptions& options, const config::SceneConfig& scene,
                                             const config::CameraScriptConfig* script, const std::string& state_file);

// The scene's default synthetic camera script (empty: none).
std::string default_script_for(const config::SceneConfig& scene);

// Whether a process ending with exit code 0 is expected, not a death: the synthetic camera
// after its script, the tracker at the end of a video file.
bool ends_by_itself(const std::string& name, const LaunchOptions& options);

}  // namespace arphys::launch
