#include "report/noise_model.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "base/errors.h"
#include "base/text_format.h"
#include "report/compare.h"
#include "report/results_identity.h"
#include "report/results_json.h"

namespace hb {

using nlohmann::json;

namespace {

struct Accumulator {
  size_t n = 0;
  double sumSq = 0, maxAbs = 0;
  void add(double v) {
    ++n;
    sumSq += v * v;
    maxAbs = std::max(maxAbs, std::abs(v));
  }
  double rms() const { return n ? std::sqrt(sumSq / static_cast<double>(n)) : 0.0; }
};

std::string textAt(const json& j, std::initializer_list<const char*> path) {
  const json* node = &j;
  for (const char* key : path) {
    if (!node->is_object() || !node->contains(key)) return {};
    node = &(*node)[key];
  }
  return node->is_string() ? node->get<std::string>() : std::string();
}

// The pair compared at --gate all, within-run noise only, or with `model`.
CompareReport comparePair(const AaPair& p, const NoiseModel* model, double thresholdPct) {
  CompareOptions o;
  o.gate = CompareGate::All;
  o.thresholdPct = thresholdPct;
  o.noise = model;
  return compareResults(p.a, p.b, o);
}

size_t gatesOf(const CompareReport& r) {
  return size_t(std::count_if(r.rows.begin(), r.rows.end(), [](const CompareRow& row) { return row.gates; }));
}

// A row's timed samples: the frame's or the pass's, as compare reads them (results::timingOf).
std::vector<double> samplesOf(const json& resultsFile, const std::string& variant, const std::string& pass) {
  for (const json& run : results::at(resultsFile, "runs"))
    if (textAt(run, {"name"}) == variant)
      return results::timingOf(pass == "frame" ? results::at(run, "frame_ms")
                                               : results::at(results::at(run, "passes"), pass.c_str()))
          .samples;
  return {};
}

// n draws with replacement, each index from the top bits of one 64-bit draw (Lemire's
// multiply-shift: the same indices on every platform, unlike std::uniform_int_distribution).
std::vector<double> resample(const std::vector<double>& from, double scale, std::mt19937_64& rng) {
  std::vector<double> out(from.size());
  for (double& v : out) v = scale * from[size_t((static_cast<unsigned __int128>(rng()) * from.size()) >> 64)];
  return out;
}

json requireField(const json& j, const char* key, const std::string& path, const std::string& where) {
  if (!j.is_object() || !j.contains(key))
    throw InputError(path + ": " + where + "." + key +
                     " is missing; regenerate the file with 'hybridbench noise A.json B.json ... --out FILE'");
  return j[key];
}

}  // namespace

const NoisePass* NoiseModel::find(const std::string& device, const std::string& tracer, const std::string& pass) const {
  for (const NoisePass& p : passes)
    if (p.device == device && p.tracer == tracer && p.pass == pass) return &p;
  return nullptr;
}

const NoiseJitter* NoiseModel::jitterOf(const std::string& device, const std::string& tracer) const {
  for (const NoiseJitter& j : jitter)
    if (j.device == device && j.tracer == tracer) return &j;
  return nullptr;
}

NoiseModel buildNoiseModel(const std::vector<AaPair>& pairs) {
  NoiseModel model;
  std::vector<std::pair<NoisePass, Accumulator>> byPass;
  std::vector<std::pair<NoiseJitter, Accumulator>> byDevice;
  for (const AaPair& p : pairs) {
    const std::string deviceA = textAt(p.a, {"context", "device", "name"});
    const std::string deviceB = textAt(p.b, {"context", "device", "name"});
    if (deviceA != deviceB)
      throw InputError("A/A pair " + p.nameA + " and " + p.nameB + ": the devices differ ('" + deviceA + "', '" +
                       deviceB + "'); an A/A pair is one config swept twice on one device model");
    CompareReport report;
    try {
      report = comparePair(p, nullptr, 5);
    } catch (const InputError& e) {
      throw InputError("A/A pair " + p.nameA + " and " + p.nameB + ": " + e.what());
    }
    const std::string device = report.b.device;  // as compare looks it up ("unknown" when unnamed)
    NoisePairSource source{p.nameA,           p.nameB,           device,        report.b.tracer,
                           report.a.revision, report.b.revision, report.a.date, report.b.date};
    for (const CompareRow& row : report.rows) {
      if (row.verdict == "not timed" || !(row.ratio > 0) || !std::isfinite(row.ratio)) continue;
      if (source.rows++ == 0) source.tracer = row.tracer;  // the key's tracer (the file's may be a sentence)
      auto it = std::find_if(byPass.begin(), byPass.end(), [&](const auto& e) {
        return e.first.device == device && e.first.tracer == row.tracer && e.first.pass == row.pass;
      });
      if (it == byPass.end()) it = byPass.insert(byPass.end(), {NoisePass{device, row.tracer, row.pass}, {}});
      it->second.add(std::log(row.ratio));
      if (row.medianA < kJitterPassMs && row.medianB < kJitterPassMs) {
        auto jt = std::find_if(byDevice.begin(), byDevice.end(),
                               [&](const auto& e) { return e.first.device == device && e.first.tracer == row.tracer; });
        if (jt == byDevice.end()) jt = byDevice.insert(byDevice.end(), {NoiseJitter{device, row.tracer}, {}});
        jt->second.add(row.medianB - row.medianA);
      }
    }
    model.pairs.push_back(source);
  }
  for (auto& [pass, acc] : byPass) {
    pass.n = acc.n;
    pass.rmsLog = acc.rms();
    pass.maxAbsLog = acc.maxAbs;
    model.passes.push_back(pass);
  }
  for (auto& [jitter, acc] : byDevice) {
    jitter.n = acc.n;
    jitter.rmsMs = acc.rms();
    model.jitter.push_back(jitter);
  }
  return model;
}

json toJson(const NoiseModel& m) {
  json pairs = json::array(), passes = json::array(), jitter = json::array();
  for (const NoisePairSource& p : m.pairs)
    pairs.push_back({{"a", p.a},
                     {"b", p.b},
                     {"device", p.device},
                     {"ray_tracing", p.tracer},
                     {"revision_a", p.revisionA},
                     {"revision_b", p.revisionB},
                     {"date_a", p.dateA},
                     {"date_b", p.dateB},
                     {"rows", p.rows}});
  for (const NoisePass& p : m.passes)
    passes.push_back({{"device", p.device},
                      {"ray_tracing", p.tracer},
                      {"pass", p.pass},
                      {"n", p.n},
                      {"rms_log", p.rmsLog},
                      {"max_abs_log", p.maxAbsLog},
                      {"band_pct", 100 * (std::exp(m.z * p.rmsLog) - 1)}});
  for (const NoiseJitter& j : m.jitter)
    jitter.push_back({{"device", j.device}, {"ray_tracing", j.tracer}, {"n", j.n}, {"rms_ms", j.rmsMs}});
  return {{"kind", "hybridbench-noise"},
          {"schema_version", kNoiseSchemaVersion},
          {"z", m.z},
          {"pairs", pairs},
          {"passes", passes},
          {"jitter", jitter}};
}

NoiseModel noiseModelFromJson(const json& j, const std::string& path) {
  if (!j.is_object() || j.value("kind", std::string()) != "hybridbench-noise")
    throw InputError(path +
                     ": not a noise file (no \"kind\": \"hybridbench-noise\"); write one with 'hybridbench noise "
                     "A.json B.json ... --out FILE'");
  if (j.value("schema_version", 0) == 1)  // its ray_tracing keys did not set a shared device's runs apart
    throw InputError(path +
                     ": noise file schema_version 1 does not key runs swept on a device shared with another sweep "
                     "apart (version 2 does); regenerate it with 'hybridbench noise A.json B.json ... --out FILE'");
  if (j.value("schema_version", 0) != kNoiseSchemaVersion)
    throw InputError(path + ": noise file schema_version " + j.value("schema_version", json()).dump() +
                     " is not supported (expected " + std::to_string(kNoiseSchemaVersion) +
                     "); regenerate it with this version of hybridbench");
  NoiseModel m;
  m.source = path;
  const json z = requireField(j, "z", path, "noise");
  if (!z.is_number() || !(z.get<double>() > 0))
    throw InputError(path + ": noise.z must be a number > 0 (the band is z standard deviations)");
  m.z = z.get<double>();
  try {
    for (const json& p : requireField(j, "pairs", path, "noise"))
      m.pairs.push_back({p.at("a"), p.at("b"), p.at("device"), p.at("ray_tracing"), p.at("revision_a"),
                         p.at("revision_b"), p.at("date_a"), p.at("date_b"), p.at("rows")});
    for (const json& p : requireField(j, "passes", path, "noise")) {
      NoisePass pass{p.at("device"), p.at("ray_tracing"), p.at("pass"),
                     p.at("n"),      p.at("rms_log"),     p.at("max_abs_log")};
      if (!(pass.rmsLog >= 0)) throw InputError(path + ": passes[].rms_log must be >= 0");
      m.passes.push_back(pass);
    }
    for (const json& p : requireField(j, "jitter", path, "noise")) {
      m.jitter.push_back({p.at("device"), p.at("ray_tracing"), p.at("n"), p.at("rms_ms")});
      if (!(m.jitter.back().rmsMs >= 0)) throw InputError(path + ": jitter[].rms_ms must be >= 0");
    }
  } catch (const json::exception& e) {
    throw InputError(path + ": a field of the noise file is missing or of the wrong type (" + e.what() +
                     "); regenerate it with 'hybridbench noise'");
  }
  return m;
}

NoiseCheck checkNoiseModel(const std::vector<AaPair>& pairs, const NoiseModel& model, double plantedPct,
                           double thresholdPct, size_t trialsPerRow) {
  NoiseCheck check;
  check.plantedPct = plantedPct;
  check.thresholdPct = thresholdPct;
  check.trialsPerRow = trialsPerRow;
  for (size_t i = 0; i < pairs.size(); ++i) {
    NoiseCheckPair c{pairs[i].nameA, pairs[i].nameB};
    const CompareReport within = comparePair(pairs[i], nullptr, thresholdPct);
    c.rows = within.rows.size();
    c.gatesWithin = gatesOf(within);
    c.gatesModel = gatesOf(comparePair(pairs[i], &model, thresholdPct));
    std::vector<AaPair> others;
    for (size_t k = 0; k < pairs.size(); ++k)
      if (k != i) others.push_back(pairs[k]);
    const NoiseModel without = buildNoiseModel(others);
    c.leaveOutCovers = without.jitterOf(model.pairs[i].device, model.pairs[i].tracer) != nullptr ||
                       std::any_of(without.passes.begin(), without.passes.end(), [&](const NoisePass& p) {
                         return p.device == model.pairs[i].device && p.tracer == model.pairs[i].tracer;
                       });
    c.gatesLeaveOut = gatesOf(comparePair(pairs[i], &without, thresholdPct));
    check.pairs.push_back(c);
  }
  // Detection: every A/A row over kDetectionMinMs, B slowed by the planted fraction.
  std::mt19937_64 rng(0x5eed53);  // fixed: the trials are the same on every run
  CompareOptions withModel, withinOnly;
  withModel.gate = withinOnly.gate = CompareGate::All;
  withModel.thresholdPct = withinOnly.thresholdPct = thresholdPct;
  withModel.noise = &model;
  struct Row {
    std::vector<double> a, b;
    RowContext context;
    std::string variant;
  };
  std::vector<std::pair<NoiseDetection, std::vector<Row>>> keys;
  for (const AaPair& p : pairs) {
    const CompareReport report = comparePair(p, nullptr, thresholdPct);
    for (const CompareRow& row : report.rows) {
      if (row.verdict == "not timed" || !(row.medianA > kDetectionMinMs)) continue;
      auto it = std::find_if(keys.begin(), keys.end(), [&](const auto& k) {
        return k.first.device == report.b.device && k.first.tracer == row.tracer && k.first.pass == row.pass;
      });
      if (it == keys.end()) it = keys.insert(keys.end(), {NoiseDetection{report.b.device, row.tracer, row.pass}, {}});
      it->second.push_back(
          {samplesOf(p.a, row.variant, row.pass), samplesOf(p.b, row.variant, row.pass),
           RowContext{report.b.device, row.tracer, results::timestampPeriodMs(p.a), results::timestampPeriodMs(p.b)},
           row.variant});
    }
  }
  // The fraction of trials that gate with B slowed by `planted` (a fraction); the generator's
  // state is restored so that every planted size sees the same resamples.
  auto detectedAt = [&](const std::vector<Row>& rows, const std::string& pass, double planted,
                        const CompareOptions& o) {
    std::mt19937_64 local = rng;
    size_t gated = 0, trials = 0;
    for (const Row& r : rows)
      for (size_t t = 0; t < trialsPerRow; ++t) {
        const CompareRow c = compareSampleSets(r.variant, pass, resample(r.a, 1, local),
                                               resample(r.b, 1 + planted, local), o, r.context);
        gated += c.gates;
        ++trials;
      }
    return trials ? double(gated) / double(trials) : 0.0;
  };
  for (auto& [d, rows] : keys) {
    d.rows = rows.size();
    d.trials = rows.size() * trialsPerRow;
    const CompareOptions& o = withModel;
    d.detected = detectedAt(rows, d.pass, plantedPct / 100, o);
    d.detectedWithin = detectedAt(rows, d.pass, plantedPct / 100, withinOnly);
    // The smallest planted slowdown gated in >= 95 % of trials: bisection on [0, 4] (a 5x slowdown),
    // to 0.1 % (the fraction gated grows with the slowdown for fixed resamples).
    double lo = 0, hi = 4;
    if (detectedAt(rows, d.pass, hi, o) < 0.95) {
      d.smallest95 = kNaN;
    } else {
      while (hi - lo > 0.001) {
        const double mid = 0.5 * (lo + hi);
        (detectedAt(rows, d.pass, mid, o) >= 0.95 ? hi : lo) = mid;
      }
      d.smallest95 = hi;
    }
    check.detection.push_back(d);
  }
  return check;
}

std::string formatNoise(const NoiseModel& m, const NoiseCheck& c) {
  std::string out = format(
      "Between-run noise of %zu A/A pairs (z = %.3f: a row of an A/A pair passes the band with probability 0.1 %% "
      "under a normal model)\n\n",
      m.pairs.size(), m.z);
  out += "| device | ray tracing | pass | A/A rows | RMS of log(B/A) | largest abs log(B/A) | band (gates beyond) |\n";
  out += "|---|---|---|---:|---:|---:|---:|\n";
  for (const NoisePass& p : m.passes)
    out += format("| %s | %s | %s | %zu%s | %.4f | %.4f | +%.2f %% |\n", p.device.c_str(), p.tracer.c_str(),
                  p.pass.c_str(), p.n, p.n < kNoiseFewRows ? " (few)" : "", p.rmsLog, p.maxAbsLog,
                  100 * (std::exp(m.z * p.rmsLog) - 1));
  out += "\nLaunch jitter (median differences of passes under 0.1 ms) and the floor it adds\n\n";
  out += "| device | ray tracing | rows | RMS (us) | z x RMS (us) |\n|---|---|---:|---:|---:|\n";
  for (const NoiseJitter& j : m.jitter)
    out += format("| %s | %s | %zu | %.3f | %.3f |\n", j.device.c_str(), j.tracer.c_str(), j.n, 1000 * j.rmsMs,
                  1000 * m.z * j.rmsMs);
  if (c.pairs.empty()) return out;  // --no-check
  out += format("\nFalse alarms: rows that gate with compare --gate all, threshold %.4g %%\n\n", c.thresholdPct);
  out += "| A | B | rows | within-run noise only | with the model (in sample) | with the other pairs' model |\n";
  out += "|---|---|---:|---:|---:|---:|\n";
  for (const NoiseCheckPair& p : c.pairs)
    out += format("| %s | %s | %zu | %zu | %zu | %zu%s |\n", p.a.c_str(), p.b.c_str(), p.rows, p.gatesWithin,
                  p.gatesModel, p.gatesLeaveOut, p.leaveOutCovers ? "" : " (no other pair of its device and tracer)");
  out += format(
      "\nDetection: a planted %.4g %% slowdown of each A/A row over %.4g ms, %zu resamples a row, threshold %.4g "
      "%%\n\n",
      c.plantedPct, kDetectionMinMs, c.trialsPerRow, c.thresholdPct);
  out +=
      "| device | ray tracing | pass | rows | gated (model) | gated (within-run only) | smallest slowdown gated in "
      "95 % |\n|---|---|---|---:|---:|---:|---:|\n";
  for (const NoiseDetection& d : c.detection)
    out += format("| %s | %s | %s | %zu | %.1f %% | %.1f %% | %s |\n", d.device.c_str(), d.tracer.c_str(),
                  d.pass.c_str(), d.rows, 100 * d.detected, 100 * d.detectedWithin,
                  std::isfinite(d.smallest95) ? format("%.1f %%", 100 * d.smallest95).c_str() : "none up to 5x");
  return out;
}

}  // namespace hb
