#include "base/version.h"

#include "git_rev.h"  // generated at build time by cmake/git_rev.cmake

namespace hb {
std::string toolVersion() { return HYBRIDBENCH_VERSION; }
std::string gitRevision() { return HYBRIDBENCH_GIT; }
}  // namespace hb
