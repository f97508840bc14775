#include "dds_test_support.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "vifusion/test/dds_domains.hpp"

extern char** environ;

namespace vifusion::dds::test {
namespace {

std::mt19937_64& generator() {
  static std::mt19937_64 engine{std::random_device{}()};
  return engine;
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

ParticipantOptions loopbackOptions() {
  ParticipantOptions options;
  options.domain_id = vifusion::test::randomSharedDomain(generator());
  options.config = VIFUSION_DDS_LOOPBACK_CONFIG;
  options.partition = "vifusion_test_" + std::to_string(::getpid()) + "_" + std::to_string(generator()());
  return options;
}

std::vector<std::string> peerParticipantArgs(const ParticipantOptions& options) {
  return {std::to_string(options.domain_id), options.partition, options.config};
}

PeerProcess::PeerProcess(const std::vector<std::string>& args) {
  dir_ = std::filesystem::temp_directory_path() /
         ("vifusion_dds_peer_" + std::to_string(::getpid()) + "_" + std::to_string(generator()()));
  std::filesystem::create_directories(dir_);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, (dir_ / "out").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, (dir_ / "err").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  std::vector<std::string> argv_text{VIFUSION_DDS_TEST_PEER};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& arg : argv_text) argv.push_back(arg.data());
  argv.push_back(nullptr);
  const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error(std::string("cannot start ") + VIFUSION_DDS_TEST_PEER);
}

PeerProcess::~PeerProcess() {
  if (running()) {
    ::kill(pid_, SIGKILL);
    wait();
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

bool PeerProcess::running() {
  if (pid_ < 0) return false;
  if (::waitpid(pid_, &status_, WNOHANG) == pid_) pid_ = -1;
  return pid_ >= 0;
}

int PeerProcess::wait() {
  if (pid_ >= 0 && ::waitpid(pid_, &status_, 0) == pid_) pid_ = -1;
  return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
}

std::string PeerProcess::out() const { return readFile(dir_ / "out"); }
std::string PeerProcess::err() const { return readFile(dir_ / "err"); }

}  // namespace vifusion::dds::test
