#include "app/sweep_console.h"

#include <unistd.h>

#include <cstdio>

#include "base/text_format.h"

namespace hb {

void Console::print(const std::string& text) const {
  std::lock_guard<std::mutex> lock(mutex());
  if (!shared()) {
    std::fputs(text.c_str(), stdout);
  } else {
    size_t start = 0;
    while (start < text.size()) {
      const size_t end = text.find('\n', start);
      const std::string line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
      std::printf("%s%s\n", prefix_.c_str(), line.c_str());
      if (end == std::string::npos) break;
      start = end + 1;
    }
  }
  std::fflush(stdout);
}

std::mutex& Console::mutex() {
  static std::mutex m;
  return m;
}

Progress::Progress(size_t total, const Console& console)
    : total_(total),
      tty_(isatty(fileno(stdout)) && !console.shared()),
      console_(console),
      start_(std::chrono::steady_clock::now()) {}

void Progress::update(size_t done, const std::string& what) {
  double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  // No estimate before the first variant finished: "eta --", not a made-up 0 s.
  const std::string eta = done ? format("%.0fs", elapsed / double(done) * double(total_ - done))
                               : std::string(done == total_ ? "0s" : "--");
  if (!tty_) {
    console_.print(format("[%zu/%zu] %s (elapsed %.0fs, eta %s)\n", done, total_, what.c_str(), elapsed, eta.c_str()));
    return;
  }
  {
    const int width = 28;
    int filled = total_ ? int(width * done / total_) : width;
    std::printf("\r[%s%s] %zu/%zu  %-44.44s  elapsed %4.0fs  eta %5s", std::string(filled, '#').c_str(),
                std::string(width - filled, '.').c_str(), done, total_, what.c_str(), elapsed, eta.c_str());
    if (done == total_) std::printf("\n");
  }
  std::fflush(stdout);
}

}  // namespace hb
