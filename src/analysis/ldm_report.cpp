#include "analysis/ldm_report.h"

#include <algorithm>
#include <vector>

namespace hb {

// The LDMs' memory and lists (issue #16: heads, nodes allocated and used, nodes per pixel).
nlohmann::json ldmJson(const LdmBuild& ldm, uint64_t linkBytes) {
  const LdmCounters c = ldm.readCounters();
  std::vector<uint32_t> lengths = ldm.readListLengths();
  std::sort(lengths.begin(), lengths.end());
  const uint64_t heads = uint64_t(lengths.size());
  const uint64_t exactBytes = ldm.exactBytes(c.allocated);  // a head per map pixel, a node per fragment
  return {{"maps", ldm.mapCount()},
          {"resolution", ldm.resolution()},
          {"heads", heads},
          {"nodes_capacity", ldm.nodeCapacity()},
          {"nodes_used", std::min<uint64_t>(c.allocated, ldm.nodeCapacity())},
          {"fragments", c.allocated},
          {"overflow", c.overflow},
          {"unfinished_insertions", c.unfinished},
          {"cas_retries", c.casRetries},
          {"fp64_edges", c.fp64Edges},
          {"chunks", c.chunks},
          {"chunk_overflow", c.chunkOverflow},
          {"chunks_capacity", ldm.chunkCapacity()},
          {"nodes_per_pixel",
           {{"mean", heads ? double(c.allocated) / double(heads) : 0.0},
            {"p99", lengths.empty() ? 0u : lengths[size_t(0.99 * double(lengths.size() - 1))]},
            {"max", lengths.empty() ? 0u : lengths.back()}}},
          {"exact_bytes", exactBytes},
          {"allocated_over_exact", exactBytes ? double(linkBytes) / double(exactBytes) : 0.0}};
}

}  // namespace hb
