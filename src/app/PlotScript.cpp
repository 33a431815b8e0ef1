#include "app/PlotScript.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

namespace flexsens {

std::string drawPlotScript(const std::string& name, const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path script = exe.parent_path().parent_path() / "scripts" / name;
  if (ec || !fs::is_regular_file(script)) return "scripts/" + name + " not found beside the build";
  const pid_t pid = ::fork();
  if (pid == 0) {  // Debian's python3 first: python3-matplotlib installs there, not into a PATH's pyenv
    ::execl("/usr/bin/python3", "python3", script.c_str(), folder.c_str(), static_cast<char*>(nullptr));
    ::execlp("python3", "python3", script.c_str(), folder.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  if (pid < 0 || ::waitpid(pid, &status, 0) < 0) return "could not start python3";
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return "python3 " + script.string() + " " + folder + " failed (python3-matplotlib missing?)";
  return "";
}

}  // namespace flexsens
