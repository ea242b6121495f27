// The child process that runs a sweep's variants (sweep_device.cpp). The sweep re-executes itself
// with the hidden flag --worker-fd: the child opens the device, runs the variants it is given and
// sends each result to the parent over a pipe, one message a line. The parent owns the results
// files, and a watchdog that ends a child that stops making progress. A driver hang ignores the
// GPU time-out and SIGTERM, so the watchdog's last word is SIGKILL. The next variant then runs in
// a fresh child with a fresh device.
#pragma once
#include <sys/types.h>

#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace hb {

// Child side: messages to the parent, each one line "kind payload" (the payload holds no newline).
class WorkerChannel {
 public:
  explicit WorkerChannel(int fd) : fd_(fd) {}
  void send(const std::string& kind, const std::string& payload = "") const;

 private:
  int fd_;
};

// The file descriptor a child writes its messages to ("--worker-fd 3").
constexpr int kWorkerFd = 3;

// The executable a sweep starts as its worker: set by the tool's main() (/proc/self/exe). Where
// none is set (a program that links the library, such as a test binary with effects of its own
// registered, where re-executing itself would run something else) the worker runs on a thread of
// this process instead: the same messages over the same pipe, but no watchdog, since a thread
// cannot be killed.
void setSweepWorkerExecutable(const std::string& path);
const std::string& sweepWorkerExecutable();

// Parent side: one child, started from sweepWorkerExecutable() with `args` (argv[1..], which must
// include "--worker-fd 3"); its stdin, stdout and stderr are the parent's. Without an executable,
// `inProcess(fd)` runs on a thread and its return value is the worker's exit code.
class WorkerProcess {
 public:
  WorkerProcess(const std::vector<std::string>& args, std::function<int(int fd)> inProcess);
  bool isThread() const { return thread_.joinable() || threadDone_; }
  ~WorkerProcess();  // a child still running is killed (SIGKILL) and reaped: none is left behind
  WorkerProcess(const WorkerProcess&) = delete;
  WorkerProcess& operator=(const WorkerProcess&) = delete;

  enum class Read { Message, Timeout, End };
  // The next message, waiting at most `seconds`: Message (kind and payload set), Timeout, or End
  // (the child closed its end: it has ended or is ending).
  Read next(double seconds, std::string& kind, std::string& payload);
  // Ends the child: SIGTERM (a sweep stops after its current frame), then SIGKILL if it has not
  // ended within graceSeconds. Returns its wait status.
  int stop(double graceSeconds);
  // Waits for the child to end; returns its wait status.
  int wait();
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  std::thread thread_;
  bool threadDone_ = false;
  int threadCode_ = 0;
  int fd_ = -1;
  std::string buffer_;
  bool reaped_ = false;
  int status_ = 0;
};

// A wait status in words: "exit code 3", "signal 9 (Killed)".
std::string describeWaitStatus(int status);

}  // namespace hb
