#include "vifusion/daemon/frame_source.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/service/log.hpp"

extern char** environ;

namespace vifusion::daemon {
namespace {

std::filesystem::path siblingProgram(const char* name) {
  return std::filesystem::read_symlink("/proc/self/exe").parent_path() / name;
}

void generateSim(const std::string& preset, const std::filesystem::path& dir) {
  const std::filesystem::path program = siblingProgram("vifusion");
  service::logLine(service::LogLevel::Info, "generating sim:%s into %s with %s", preset.c_str(), dir.c_str(),
                   program.c_str());
  std::filesystem::remove_all(dir);  // an interrupted earlier generation
  std::vector<std::string> args = {program.string(), "sim", "--preset", preset, "--out", dir.string()};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    throw Error("source 'sim:" + preset + "': cannot start " + program.string());
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error("source 'sim:" + preset + "': `vifusion sim --preset " + preset + "` failed");
  }
}

}  // namespace

std::unique_ptr<datasets::DatasetReader> openSource(const std::string& source, const std::string& out_dir) {
  if (!source.starts_with("sim:")) return datasets::openDataset(source);
  const std::string preset = source.substr(4);
  const std::filesystem::path dir = std::filesystem::path(out_dir) / ("sim_" + preset);
  if (!std::filesystem::exists(dir / "rgb.txt")) generateSim(preset, dir);
  return datasets::openDataset("dataset:" + dir.string());
}

}  // namespace vifusion::daemon
