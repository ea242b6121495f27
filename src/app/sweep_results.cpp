#include "app/sweep_results.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "base/text_format.h"
#include "report/accuracy_report.h"
#include "report/all_tables.h"
#include "report/html_report.h"
#include "report/roofline.h"
#include "report/tables.h"

namespace hb {

namespace fs = std::filesystem;
using json = nlohmann::json;

void writeFileAtomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throw InputError("cannot write " + path + "; check that the directory exists and is writable");
    f << text;
    f.flush();
    if (!f) throw InputError("cannot write " + path + " (disk full?)");
  }
  fs::rename(tmp, path);
}

std::string slug(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (std::isalnum(static_cast<unsigned char>(c)))
      out += asciiLower(c);
    else if (!out.empty() && out.back() != '-')
      out += '-';
  }
  while (!out.empty() && out.back() == '-') out.pop_back();
  return out.empty() ? "run" : out;
}

std::string resultsCsv(const json& results) {
  std::ostringstream o;
  o << "run,status,tile_size,light_culling,aabb,normal_culling,backend,width,height,world_pos,range_test,"
       "depth_slices,t_min,light_count,triangle_scale,pass,median_ms,mean_ms,stddev_ms,min_ms,max_ms,p95_ms,samples,"
       "rays_traced,"
       "rays_oracle\n";
  auto q = [](const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string r = "\"";
    for (char c : s) r += c == '"' ? std::string("\"\"") : std::string(1, c);
    return r + "\"";
  };
  auto num = [](const json& j, const char* key) -> std::string {
    if (!j.is_object() || !j.contains(key) || !j[key].is_number()) return "";
    std::ostringstream s;
    s.precision(9);
    s << j[key].get<double>();
    return s.str();
  };
  const json runs = results.value("runs", json::array());
  for (const json& run : runs) {
    const json p = run.value("params", json::object());
    std::ostringstream prefix;
    auto str = [](const json& j) { return j.is_string() ? j.get<std::string>() : j.is_null() ? "" : j.dump(); };
    prefix << q(run.value("name", "")) << "," << run.value("status", "") << "," << str(p.value("tile_size", json()))
           << "," << str(p.value("light_culling", json())) << "," << str(p.value("aabb", json())) << ","
           << str(p.value("normal_culling", json())) << "," << str(p.value("backend", json())) << ",";
    json res = p.value("resolution", json::array({0, 0}));
    prefix << res[0] << "," << res[1] << "," << str(p.value("world_pos", json())) << ","
           << str(p.value("range_test", json())) << "," << str(p.value("depth_slices", json())) << ","
           << str(p.value("t_min", json())) << "," << str(p.value("light_count", json())) << ","
           << str(p.value("triangle_scale", json()));
    const json rays = run.value("rays", json::object());
    const std::string tail = "," + num(rays, "traced") + "," + num(rays, "oracle") + "\n";
    auto row = [&](const std::string& pass, const json& s) {
      o << prefix.str() << "," << pass << "," << num(s, "median") << "," << num(s, "mean") << "," << num(s, "stddev")
        << "," << num(s, "min") << "," << num(s, "max") << "," << num(s, "p95") << ","
        << (s.contains("samples") ? s["samples"].size() : 0) << tail;
    };
    if (run.value("status", "") != "ok") {
      o << prefix.str() << ",,,,,,,,0,,\n";
      continue;
    }
    row("frame", run["frame_ms"]);
    const json passes = run.value("passes", json::object());
    for (const auto& [pass, s] : passes.items()) row(pass, s);
  }
  return o.str();
}

void writeSweepOutputs(const std::string& dir, const json& results) {
  writeFileAtomic((fs::path(dir) / "results.json").string(), results.dump(1) + "\n");
  writeFileAtomic((fs::path(dir) / "results.csv").string(), resultsCsv(results));
  { writeFileAtomic((fs::path(dir) / "tables.md").string(), allTablesMarkdown(results)); }
  writeFileAtomic((fs::path(dir) / "accuracy.md").string(), accuracyReportMarkdown(results));
  writeFileAtomic((fs::path(dir) / "accuracy.svg").string(), accuracyReportSvg(results));
  writeFileAtomic((fs::path(dir) / "roofline.md").string(), rooflineMarkdown(results));
  writeFileAtomic((fs::path(dir) / "roofline.svg").string(), rooflineSvg(results));
  HtmlReportInput page;
  page.results = &results;
  page.source = "results.json";
  page.images = variantImages(dir, dir, results);
  writeFileAtomic((fs::path(dir) / "report.html").string(), htmlReport(page));
}

std::map<std::string, std::vector<ReportImage>> variantImages(const std::string& resultsDir,
                                                              const std::string& reportDir, const json& results) {
  std::map<std::string, std::vector<ReportImage>> out;
  if (!results.contains("runs") || !results["runs"].is_array()) return out;
  // Both made absolute and normal, so that the relative path does not depend on how they were named.
  const fs::path from = fs::weakly_canonical(fs::absolute(reportDir));
  for (const json& run : results["runs"]) {
    if (!run.is_object() || !run.contains("name") || !run["name"].is_string()) continue;
    const std::string name = run["name"].get<std::string>();
    const fs::path folder = fs::weakly_canonical(fs::absolute(fs::path(resultsDir) / slug(name)));
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) continue;
    // Each image by its name without extension: the PNG the sweep wrote, or its WebP preview
    // (scripts/previews.sh; the only one committed under results/), which wins when both are there.
    std::map<std::string, std::string> files;
    for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
      const fs::path& p = e.path();
      if (!e.is_regular_file(ec) || (p.extension() != ".png" && p.extension() != ".webp")) continue;
      std::string& file = files[p.stem().string()];
      if (file.empty() || p.extension() == ".webp") file = p.filename().string();
    }
    std::vector<std::pair<std::string, std::string>> ordered(files.begin(), files.end());
    // The colour image first (what the variant looks like), then by name: heatmaps and error maps
    // of one kind sit together (rays, rays_oracle; flip_error).
    std::stable_partition(ordered.begin(), ordered.end(), [](const auto& f) { return f.first == "color"; });
    for (const auto& [stem, file] : ordered) {
      std::string label = stem;
      std::replace(label.begin(), label.end(), '_', ' ');
      out[name].push_back({(folder / file).lexically_relative(from).generic_string(), label});
    }
  }
  return out;
}

}  // namespace hb
