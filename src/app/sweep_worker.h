// The child process that runs a sweep's variants (sweep_device.cpp). The sweep re-executes itself
// with the hidden flag --worker-fd: the child opens the device, runs the variants it is given and
// sends each result to the parent over a pipe, one message a line. The parent owns the results
// files, and a watchdog that ends a child that stops making progress. A driver hang ignores the
// GPU time-out and SIGTERM, so the watchdog's last word is SIGKILL. The next variant then runs in
// a fresh child with a fresh device.
#pragma once
#include <sys/types.h>

#include <string>
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

// Parent side: one child, started from this same executable (/proc/self/exe) with `args`
// (argv[1..], which must include "--worker-fd 3"). Its stdin, stdout and stderr are the parent's.
class WorkerProcess {
 public:
  explicit WorkerProcess(const std::vector<std::string>& args);
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
  int fd_ = -1;
  std::string buffer_;
  bool reaped_ = false;
  int status_ = 0;
};

// A wait status in words: "exit code 3", "signal 9 (Killed)".
std::string describeWaitStatus(int status);

}  // namespace hb
