#pragma once
// The launcher's children: started with their output in a log, watched without blocking,
// restarted when asked (their logs and recordings to new files, nothing overwritten), and
// stopped together.
#include <sys/types.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace arphys::launch {

struct Child {
  std::string name;
  std::vector<std::string> args;
  pid_t pid = -1;
  bool exited = false;
  int status = 0;  // waitpid's
};

class Supervisor {
 public:
  // log_dir empty: children write to the launcher's own stdout and stderr.
  explicit Supervisor(std::string log_dir) : log_dir_(std::move(log_dir)) {}

  // False when the process cannot be started (the reason is printed).
  bool start(const std::string& name, const std::vector<std::string>& args);

  // Reaps children that exited. expected(child) tells an end that is not a death (a frame
  // source at its end). With restart, a dead child is started again; else the first dead
  // one's name is returned (empty: none).
  std::string poll(bool restart, const std::function<bool(const Child&)>& expected);

  // SIGTERM to every running child, then waits for each.
  void stop_all();

  const Child* find(const std::string& name) const;
  const std::map<std::string, int>& restarts() const { return restarts_; }
  std::string log_of(const std::string& name) const { return log_dir_.empty() ? "" : log_dir_ + "/" + name + ".log"; }

 private:
  void restart(Child& child);

  std::string log_dir_;
  std::vector<Child> children_;
  std::map<std::string, int> restarts_;
};

}  // namespace arphys::launch
