#include "tools/launch/supervisor.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>

extern char** environ;

namespace arphys::launch {
namespace {

pid_t spawn(const std::vector<std::string>& args, const std::string& log_path) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!log_path.empty()) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  }
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

// "dir/run.lcmlog" -> "dir/run.2.lcmlog" for restart 2.
std::string numbered(const std::string& path, const std::string& extension, int n) {
  return path.substr(0, path.size() - extension.size()) + "." + std::to_string(n) + extension;
}

}  // namespace

bool Supervisor::start(const std::string& name, const std::vector<std::string>& args) {
  Child c;
  c.name = name;
  c.args = args;
  c.pid = spawn(args, log_of(name));
  children_.push_back(c);
  if (c.pid <= 0) {
    std::fprintf(stderr, "arphys-launch: cannot start %s (%s)\n", name.c_str(), args[0].c_str());
    return false;
  }
  return true;
}

// The others keep running; the process comes back on the same channels and resynchronises
// from the traffic (the simulator resumes its virtual bodies from its state file). What it
// writes goes to new files: nothing recorded is lost.
void Supervisor::restart(Child& c) {
  const int n = ++restarts_[c.name];
  const std::string log = log_dir_.empty() ? std::string() : numbered(log_of(c.name), ".log", n);
  if (c.name == "recorder") c.args.back() = numbered(log_dir_ + "/run.lcmlog", ".lcmlog", n);
  for (std::size_t i = 0; i + 1 < c.args.size(); ++i) {
    if (c.args[i] == "--video") c.args[i + 1] = numbered(log_dir_ + "/overlay.avi", ".avi", n);
  }
  std::fprintf(stderr, "arphys-launch: %s died (%s %d), restarting it (restart %d)\n", c.name.c_str(),
               WIFSIGNALED(c.status) ? "signal" : "exit code",
               WIFSIGNALED(c.status) ? WTERMSIG(c.status) : WEXITSTATUS(c.status), n);
  c.pid = spawn(c.args, log);
  c.exited = c.pid <= 0;
}

std::string Supervisor::poll(bool restart_dead, const std::function<bool(const Child&)>& expected) {
  std::string died;
  for (Child& c : children_) {
    if (c.exited || c.pid <= 0) continue;
    if (waitpid(c.pid, &c.status, WNOHANG) != c.pid) continue;
    c.exited = true;
    if (expected(c)) continue;
    if (restart_dead) {
      restart(c);
    } else if (died.empty()) {
      died = c.name;
    }
  }
  return died;
}

void Supervisor::stop_all() {
  for (Child& c : children_) {
    if (!c.exited && c.pid > 0) kill(c.pid, SIGTERM);
  }
  for (Child& c : children_) {
    if (!c.exited && c.pid > 0) waitpid(c.pid, &c.status, 0);
  }
}

const Child* Supervisor::find(const std::string& name) const {
  for (const Child& c : children_) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

}  // namespace arphys::launch
