// Running the built hybridbench from end-to-end tests: each test gets a scratch directory; the
// tool runs there with stdout and stderr in files (no pipe can fill up and block) and
// HYBRIDBENCH_VALIDATION=1 whatever the test's own environment says. A test file takes every name
// here with `using namespace hb::testing;` (fs, json, the readers, ToolTest).
#pragma once
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "base/input_file.h"

#ifndef HYBRIDBENCH_BINARY
#error "HYBRIDBENCH_BINARY must name the built hybridbench executable"
#endif
#ifndef HYBRIDBENCH_SOURCE_DIR
#error "HYBRIDBENCH_SOURCE_DIR must name the source tree (configs/, scenes/, tests/fixtures/, results/)"
#endif

extern char** environ;

namespace hb::testing {

namespace fs = std::filesystem;
using nlohmann::json;

struct RunResult {
  int exitCode = -1;  // the child's exit status; 128 + signal if a signal ended it
  std::string out;
  std::string err;
};

inline std::string readFile(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The file parsed as JSON (a committed results.json.gz inflated, as the tool reads it); a discarded
// value (is_discarded()) when it is not JSON or cannot be read.
inline nlohmann::json readJson(const fs::path& p) {
  std::string text;
  try {
    text = hb::readInputText(p, "a JSON file");
  } catch (const std::exception&) {
    return nlohmann::json(nlohmann::json::value_t::discarded);
  }
  return nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
}

// The sweeps' smallest config (two variants on a small scene).
inline const fs::path kSweepFixture = fs::path(HYBRIDBENCH_SOURCE_DIR) / "tests/fixtures/sweep-tiny.json";

inline void writeFile(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
}

// The rows ("| ..." lines) of the first table in the section of a Markdown file headed `heading`
// (a "## " line), header and separator rows included.
inline std::vector<std::string> markdownTableRows(const std::string& md, const std::string& heading) {
  std::vector<std::string> rows;
  std::istringstream in(md);
  bool inSection = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## ", 0) == 0) {
      if (inSection) break;
      inSection = line == heading;
      continue;
    }
    if (!inSection) continue;
    if (line.rfind("|", 0) == 0)
      rows.push_back(line);
    else if (!rows.empty())
      break;
  }
  return rows;
}

// The glTF accessor of one triangle's positions (0,0,0) (1,0,0) (0,1,0): floats, VEC3, bufferView 0.
inline json trianglePositionsAccessor() {
  return {{"bufferView", 0}, {"componentType", 5126}, {"count", 3},
          {"type", "VEC3"},  {"min", {0, 0, 0}},      {"max", {1, 1, 0}}};
}

// Every file and folder under root (the children's .stdout/.stderr captures left out) with its
// bytes: two equal snapshots mean nothing was created, removed or changed.
inline std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> out;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
    const std::string rel = fs::relative(e.path(), root).string();
    if (rel.rfind(".std", 0) == 0) continue;
    out[rel] = e.is_regular_file() ? readFile(e.path()) : std::string("<dir>");
  }
  return out;
}

// The processes alive now whose command line holds `needle` (e.g. a test's scratch directory),
// as "pid: command line" (zombies, which hold no command line, are not listed).
inline std::vector<std::string> processesMentioning(const std::string& needle) {
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string pid = entry.path().filename().string();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmdline = readFile(entry.path() / "cmdline");
    for (char& c : cmdline)
      if (c == '\0') c = ' ';
    if (cmdline.find(needle) != std::string::npos) found.push_back(pid + ": " + cmdline);
  }
  return found;
}

class ToolTest : public ::testing::Test {
 protected:
  static constexpr std::chrono::seconds kChildDeadline{300};

  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() / (std::string("hybridbench_") + info->test_suite_name() + "_" +
                                       std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }

  // Starts hybridbench with args; returns the pid (0: the spawn failed, already reported).
  pid_t start(const std::vector<std::string>& args) {
    ++children_;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, outPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, errPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    // HYBRIDBENCH_TEST_BINARY runs the tests against another build, e.g. an older revision's, to
    // see a test fail where the behaviour it checks is missing.
    const char* other = std::getenv("HYBRIDBENCH_TEST_BINARY");
    std::vector<std::string> argv{other && *other ? other : HYBRIDBENCH_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> cargv;
    for (auto& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    std::vector<std::string> env{"HYBRIDBENCH_VALIDATION=1"};
    for (char** e = environ; *e; ++e)
      if (std::strncmp(*e, "HYBRIDBENCH_VALIDATION=", 23) != 0) env.emplace_back(*e);
    std::vector<char*> cenv;
    for (auto& e : env) cenv.push_back(e.data());
    cenv.push_back(nullptr);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, cargv[0], &actions, nullptr, cargv.data(), cenv.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
      ADD_FAILURE() << "posix_spawn " << HYBRIDBENCH_BINARY << " failed: " << std::strerror(rc);
      return 0;
    }
    return pid;
  }

  // Waits for the child (killing it past kChildDeadline) and checks that the validation layer
  // reported nothing.
  RunResult wait(pid_t pid) {
    RunResult r;
    if (pid == 0) return r;
    const auto deadline = std::chrono::steady_clock::now() + kChildDeadline;
    int status = 0;
    while (true) {
      const pid_t w = waitpid(pid, &status, WNOHANG);
      if (w == pid) break;
      if (w < 0 && errno != EINTR) {
        ADD_FAILURE() << "waitpid: " << std::strerror(errno);
        return r;
      }
      if (std::chrono::steady_clock::now() > deadline) {
        ADD_FAILURE() << "hybridbench ran past " << kChildDeadline.count() << " s; killed";
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = readFile(outPath());
    r.err = readFile(errPath());
    EXPECT_EQ(r.out.find("validation:"), std::string::npos) << r.out;
    EXPECT_EQ(r.err.find("validation:"), std::string::npos) << r.err;
    return r;
  }

  RunResult run(const std::vector<std::string>& args) { return wait(start(args)); }

  // A refusal, as every error a user can cause must be: exit 2, ONE stderr line holding each of
  // `names` and none of `absent`, nothing on stdout, and the test folder unchanged (every file's
  // bytes compared before and after, nothing created).
  RunResult expectRefused(const std::vector<std::string>& args, const std::vector<std::string>& names,
                          const std::vector<std::string>& absent = {}) {
    std::string cmd;
    for (const auto& a : args) cmd += " " + a;
    SCOPED_TRACE("hybridbench" + cmd);
    const auto before = snapshot(dir);
    const RunResult r = run(args);
    EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "stderr must be one line: " << r.err;
    EXPECT_TRUE(!r.err.empty() && r.err.back() == '\n') << "stderr must end its line: " << r.err;
    EXPECT_TRUE(r.out.empty()) << "printed before refusing: " << r.out;
    for (const auto& n : names) EXPECT_NE(r.err.find(n), std::string::npos) << "does not name " << n << ": " << r.err;
    for (const auto& n : absent) EXPECT_EQ(r.err.find(n), std::string::npos) << "says " << n << ": " << r.err;
    EXPECT_TRUE(snapshot(dir) == before) << "the refused run created or changed files";
    return r;
  }

  // Polls out/results.json until it holds at least `runs` runs (a sweep replaces it atomically, so
  // every read parses); false if the child exits first or past kChildDeadline.
  bool waitForRuns(pid_t pid, const fs::path& out, size_t runs) {
    const auto deadline = std::chrono::steady_clock::now() + kChildDeadline;
    while (std::chrono::steady_clock::now() < deadline) {
      const nlohmann::json r = readJson(out / "results.json");
      if (!r.is_discarded() && r.value("runs", nlohmann::json::array()).size() >= runs) return true;
      int status = 0;
      if (waitpid(pid, &status, WNOHANG) == pid) {
        ADD_FAILURE() << "hybridbench exited before " << runs << " run(s) were written";
        return false;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ADD_FAILURE() << "no " << runs << " run(s) in " << out / "results.json"
                  << " before the deadline";
    return false;
  }

  fs::path outPath() const { return dir / (".stdout" + std::to_string(children_)); }
  fs::path errPath() const { return dir / (".stderr" + std::to_string(children_)); }

  fs::path dir;
  int children_ = 0;
};

}  // namespace hb::testing
