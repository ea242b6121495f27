#pragma once
#include <string>
namespace hb {
std::string toolVersion();  // semantic version of hybridbench
std::string gitRevision();  // short hash of the build's commit ("unknown" outside git)
}  // namespace hb
