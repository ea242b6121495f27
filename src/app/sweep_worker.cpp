#include "app/sweep_worker.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace hb {

void WorkerChannel::send(const std::string& kind, const std::string& payload) const {
  std::string line = kind;
  if (!payload.empty()) line += " " + payload;
  for (char& c : line)
    if (c == '\n') c = ' ';
  line += '\n';
  // One write a message (a pipe writes up to PIPE_BUF bytes at once; longer ones in pieces, which
  // is fine: only this thread writes).
  size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::write(fd_, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent is gone: nothing to tell
    done += size_t(n);
  }
}

namespace {
std::string& workerExecutable() {
  static std::string path;
  return path;
}
}  // namespace

void setSweepWorkerExecutable(const std::string& path) { workerExecutable() = path; }
const std::string& sweepWorkerExecutable() { return workerExecutable(); }

WorkerProcess::WorkerProcess(const std::vector<std::string>& args, std::function<int(int fd)> inProcess) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  if (sweepWorkerExecutable().empty()) {
    fd_ = fds[0];
    const int writeEnd = fds[1];
    thread_ = std::thread([this, writeEnd, run = std::move(inProcess)] {
      try {
        threadCode_ = run(writeEnd);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "hybridbench: %s\n", e.what());
        threadCode_ = 3;
      }
      ::close(writeEnd);  // the parent reads the end of the pipe
    });
    return;
  }
  // The child's end moves to kWorkerFd; keep it off that number here, where dup2 would not clear
  // close-on-exec.
  const int writeEnd = ::fcntl(fds[1], F_DUPFD_CLOEXEC, 10);
  ::close(fds[1]);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, writeEnd, kWorkerFd);
  std::vector<std::string> argv = {"hybridbench"};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> cargv;
  for (std::string& a : argv) cargv.push_back(a.data());
  cargv.push_back(nullptr);
  const int rc = ::posix_spawn(&pid_, sweepWorkerExecutable().c_str(), &actions, nullptr, cargv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(writeEnd);
  if (rc != 0) {
    ::close(fds[0]);
    throw std::runtime_error(std::string("cannot start the sweep's worker process: ") + std::strerror(rc));
  }
  fd_ = fds[0];
}

WorkerProcess::~WorkerProcess() {
  if (thread_.joinable()) wait();
  if (!reaped_ && pid_ > 0) {
    ::kill(pid_, SIGKILL);
    wait();
  }
  if (fd_ >= 0) ::close(fd_);
}

WorkerProcess::Read WorkerProcess::next(double seconds, std::string& kind, std::string& payload) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    const size_t eol = buffer_.find('\n');
    if (eol != std::string::npos) {
      const std::string line = buffer_.substr(0, eol);
      buffer_.erase(0, eol + 1);
      const size_t space = line.find(' ');
      kind = line.substr(0, space);
      payload = space == std::string::npos ? "" : line.substr(space + 1);
      return Read::Message;
    }
    if (fd_ < 0) return Read::End;
    const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) return Read::Timeout;
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, int(left * 1000.0) + 1);
    if (ready < 0 && errno == EINTR) continue;  // a signal (Ctrl-C): the caller looks at its flag
    if (ready <= 0) {
      if (ready == 0) continue;  // the deadline check above ends the wait
      return Read::End;
    }
    char chunk[65536];
    const ssize_t n = ::read(fd_, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ::close(fd_);
      fd_ = -1;
      if (buffer_.empty()) return Read::End;
      buffer_ += '\n';  // a last line without its newline
      continue;
    }
    buffer_.append(chunk, size_t(n));
  }
}

int WorkerProcess::wait() {
  if (reaped_) return status_;
  if (thread_.joinable() || threadDone_) {  // a thread: its exit code as a wait status
    while (fd_ >= 0) {                      // drain what it still writes, so that it cannot block on a full pipe
      std::string kind, payload;
      if (next(1.0, kind, payload) == Read::End) break;
    }
    if (thread_.joinable()) thread_.join();
    threadDone_ = true;
    reaped_ = true;
    status_ = (threadCode_ & 0xff) << 8;
    return status_;
  }
  while (::waitpid(pid_, &status_, 0) < 0 && errno == EINTR) {
  }
  reaped_ = true;
  return status_;
}

int WorkerProcess::stop(double graceSeconds) {
  if (reaped_) return status_;
  if (thread_.joinable() || threadDone_) return wait();  // a thread ends at its next frame (the sweep's interrupt flag)
  ::kill(pid_, SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(graceSeconds);
  while (std::chrono::steady_clock::now() < deadline) {
    const pid_t r = ::waitpid(pid_, &status_, WNOHANG);
    if (r == pid_) {
      reaped_ = true;
      return status_;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(pid_, SIGKILL);
  return wait();
}

std::string describeWaitStatus(int status) {
  if (WIFEXITED(status)) return "exit code " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = ::strsignal(sig);
    return "signal " + std::to_string(sig) + (name ? std::string(" (") + name + ")" : "");
  }
  return "wait status " + std::to_string(status);
}

}  // namespace hb
