// A sweep's console output: whole lines to stdout, shared safely between the threads of
// `--device all`, and the progress bar (a line per variant where stdout is no terminal or shared).
#pragma once
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace hb {

// One device's console output. When several devices sweep at once (`--device all`) stdout is
// shared: every write is whole lines under one lock, each line prefixed with the device
// ("[1 NVIDIA H200] "), and the progress bar becomes a line per variant.
class Console {
 public:
  explicit Console(std::string prefix = "") : prefix_(std::move(prefix)) {}
  bool shared() const { return !prefix_.empty(); }
  void print(const std::string& text) const;
  static std::mutex& mutex();

 private:
  std::string prefix_;
};

// Precondition: `console` outlives the Progress.
class Progress {
 public:
  Progress(size_t total, const Console& console);
  void update(size_t done, const std::string& what);

 private:
  size_t total_;
  bool tty_;
  const Console& console_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace hb
