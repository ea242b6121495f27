// For tests that run the analyses on a chosen number of threads (parallel.h analysisThreads reads
// HYBRIDBENCH_THREADS): parallel_test.cpp, analysis/analysis_threads_test.cpp.
#pragma once
#include <cstdlib>
#include <string>

namespace hb {

// Sets HYBRIDBENCH_THREADS to `value` (nullptr: unsets it) for the life of the object, then puts
// back what was there: scripts/sanitize.sh sets it for the whole ThreadSanitizer run. The
// environment is the process's; no other thread may read it meanwhile (parallelFor reads it once,
// before it starts its threads).
class ScopedAnalysisThreads {
 public:
  explicit ScopedAnalysisThreads(const char* value) {
    if (const char* old = std::getenv(kName)) saved_ = old, hadValue_ = true;
    set(value);
  }
  explicit ScopedAnalysisThreads(unsigned threads) : ScopedAnalysisThreads(std::to_string(threads).c_str()) {}
  ~ScopedAnalysisThreads() { set(hadValue_ ? saved_.c_str() : nullptr); }
  ScopedAnalysisThreads(const ScopedAnalysisThreads&) = delete;
  ScopedAnalysisThreads& operator=(const ScopedAnalysisThreads&) = delete;

 private:
  static constexpr const char* kName = "HYBRIDBENCH_THREADS";
  static void set(const char* value) {
    if (value)
      setenv(kName, value, 1);
    else
      unsetenv(kName);
  }
  std::string saved_;
  bool hadValue_ = false;
};

}  // namespace hb
