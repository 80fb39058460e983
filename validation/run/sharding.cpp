#include "validation/run/sharding.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <set>
#include <stdexcept>

namespace pbdval {
namespace {

/// FNV-1a, 64 bit, over a sequence of fields (each followed by a 0 byte, so that field
/// boundaries count).
class Digest {
 public:
  void add(const std::string& field) {
    for (unsigned char c : field)
      mix(c);
    mix(0);
  }
  std::string hex() const {
    static const char* digits = "0123456789abcdef";
    std::string text(16, '0');
    for (int i = 0; i < 16; ++i)
      text[std::size_t(i)] = digits[(hash_ >> (60 - 4 * i)) & 0xf];
    return text;
  }

 private:
  void mix(unsigned char c) {
    hash_ ^= c;
    hash_ *= 1099511628211ULL;
  }
  std::uint64_t hash_ = 14695981039346656037ULL;
};

std::size_t sliceSize(std::size_t requests, int index, int count) {
  // Positions p < requests with p mod count = index − 1.
  const std::size_t first = std::size_t(index - 1);
  return first < requests ? (requests - first - 1) / std::size_t(count) + 1 : 0;
}

bool sameBuild(const RunMetadata& a, const RunMetadata& b) {
  return a.version == b.version && a.commit == b.commit && a.commitState == b.commitState &&
         a.buildType == b.buildType && a.compiler == b.compiler && a.flags == b.flags &&
         a.precision == b.precision;
}

std::string buildText(const RunMetadata& m) {
  return "pbdval " + m.version + " commit " + m.commit.substr(0, 12) +
         (m.commitState == "clean" || m.commitState.empty() ? "" : " (" + m.commitState + ")") +
         ", " + m.buildType + ", " + m.compiler + ", " + m.precision;
}

}  // namespace

ShardInfo parseShard(const std::string& text) {
  ShardInfo shard;
  const std::size_t slash = text.find('/');
  auto number = [&](std::size_t from, std::size_t to, int& out) {
    const char* begin = text.data() + from;
    const char* end = text.data() + to;
    const auto r = std::from_chars(begin, end, out);
    return begin != end && r.ec == std::errc() && r.ptr == end;
  };
  if (slash == std::string::npos || !number(0, slash, shard.index) ||
      !number(slash + 1, text.size(), shard.count) || shard.count < 1 || shard.index < 1 ||
      shard.index > shard.count)
    throw std::invalid_argument("--shard: expected K/N with 1 <= K <= N (e.g. 3/8), got '" + text +
                                "'");
  return shard;
}

namespace {

/// The fields of a request that make it this run (not where its trajectory goes).
void addRun(Digest& d, const RunRequest& r) {
  d.add(r.caseName);
  d.add(r.caseFile);
  d.add(r.engine);
  d.add(r.method);
  for (const std::string& a : r.assignments)
    d.add(a);
  d.add("|");
  d.add(r.referenceMode);
  d.add(std::to_string(r.fineDivisor));
  d.add(std::to_string(r.referenceStepSize));
  d.add(std::to_string(r.sampleInterval));
}

void addUnreadable(Digest& d, const RunPlan& plan) {
  for (const RunRecord& u : plan.unreadable) {
    d.add("unreadable");
    d.add(u.request.caseFile);
  }
}

}  // namespace

std::string planDigest(const RunPlan& plan) {
  Digest d;
  for (const RunRequest& r : plan.requests) {
    addRun(d, r);
    d.add(r.trajectoryPath.empty() ? "no-trajectory" : "trajectory");
  }
  addUnreadable(d, plan);
  return d.hex();
}

std::string runsDigest(const RunPlan& plan) {
  Digest d;
  for (const RunRequest& r : plan.requests)
    addRun(d, r);
  addUnreadable(d, plan);
  return d.hex();
}

std::string planDigestOfRuns(const std::vector<RunRecord>& runs) {
  RunPlan plan;
  for (const RunRecord& r : runs) {
    if (r.request.engine == "-")
      plan.unreadable.push_back(r);
    else
      plan.requests.push_back(r.request);
  }
  return runsDigest(plan);
}

RunPlan shardOf(const RunPlan& plan, ShardInfo& shard) {
  shard.planSize = plan.requests.size() + plan.unreadable.size();
  shard.planDigest = planDigest(plan);
  RunPlan part;
  for (std::size_t p = std::size_t(shard.index - 1); p < plan.requests.size();
       p += std::size_t(shard.count))
    part.requests.push_back(plan.requests[p]);
  if (shard.index == 1) part.unreadable = plan.unreadable;
  for (const RunRequest& r : part.requests)
    if (plan.cases.count(r.caseName)) part.cases[r.caseName] = plan.cases.at(r.caseName);
  return part;
}

ResultsFile mergeShards(const std::vector<ShardResults>& shards, const std::string& command) {
  if (shards.empty()) throw std::invalid_argument("no shard folders given");
  for (const ShardResults& s : shards)
    if (!s.results.metadata.shard)
      throw std::invalid_argument(s.folder +
                                  ": not a shard (results of 'pbdval run' without --shard)");
  const ShardResults& first = shards.front();
  const ShardInfo& plan = *first.results.metadata.shard;
  std::vector<const ShardResults*> byIndex(std::size_t(plan.count), nullptr);
  for (const ShardResults& s : shards) {
    const ShardInfo& info = *s.results.metadata.shard;
    if (info.count != plan.count || info.planDigest != plan.planDigest ||
        info.planSize != plan.planSize)
      throw std::invalid_argument(s.folder + ": shard of another plan (" +
                                  std::to_string(info.count) + " shards, plan " + info.planDigest +
                                  ") than " + first.folder + " (" + std::to_string(plan.count) +
                                  " shards, plan " + plan.planDigest + ")");
    if (!sameBuild(s.results.metadata, first.results.metadata))
      throw std::invalid_argument(s.folder + ": made by another build (" +
                                  buildText(s.results.metadata) + ") than " + first.folder + " (" +
                                  buildText(first.results.metadata) + ")");
    const std::size_t slot = std::size_t(info.index - 1);
    if (byIndex[slot])
      throw std::invalid_argument("shard " + std::to_string(info.index) + "/" +
                                  std::to_string(info.count) +
                                  " given twice: " + byIndex[slot]->folder + " and " + s.folder);
    byIndex[slot] = &s;
  }
  std::string missing;
  for (std::size_t k = 0; k < byIndex.size(); ++k)
    if (!byIndex[k]) missing += (missing.empty() ? "" : ", ") + std::to_string(k + 1);
  if (!missing.empty())
    throw std::invalid_argument("missing shard(s) " + missing + " of " +
                                std::to_string(plan.count));

  // The unreadable cases are shard 1's records of status error with engine "-".
  // (indices into the shards: each record is copied once, into the merged results, with its
  // text when the shard was read with it: readResultsCopyingRecords)
  std::vector<std::vector<std::size_t>> runs(byIndex.size());
  std::vector<std::size_t> unreadable;
  for (std::size_t k = 0; k < byIndex.size(); ++k)
    for (std::size_t i = 0; i < byIndex[k]->results.runs.size(); ++i)
      (k == 0 && byIndex[k]->results.runs[i].request.engine == "-" ? unreadable : runs[k])
          .push_back(i);
  const std::size_t requests = plan.planSize - unreadable.size();
  for (std::size_t k = 0; k < byIndex.size(); ++k) {
    const std::size_t expected = sliceSize(requests, int(k + 1), plan.count);
    if (runs[k].size() != expected)
      throw std::invalid_argument(byIndex[k]->folder + ": holds " + std::to_string(runs[k].size()) +
                                  " runs, its slice of the plan has " + std::to_string(expected));
  }

  ResultsFile merged;
  merged.metadata = first.results.metadata;
  merged.metadata.shard.reset();
  merged.metadata.command = command;
  std::set<std::string> hosts;
  for (const ShardResults& s : shards)
    hosts.insert(s.results.metadata.hostname);
  merged.metadata.hostname.clear();
  for (const std::string& h : hosts)
    merged.metadata.hostname += (merged.metadata.hostname.empty() ? "" : ",") + h;
  merged.runs.reserve(unreadable.size() + requests);
  const auto take = [&](std::size_t k, std::size_t i) {
    const ResultsFile& shard = byIndex[k]->results;
    merged.runs.push_back(shard.runs[i]);
    const bool text = i < shard.recordTexts.size() && !shard.recordTexts[i].empty();
    if (text) {
      merged.recordTexts.resize(merged.runs.size());
      merged.recordTexts.back() = shard.recordTexts[i];
    }
  };
  for (const std::size_t i : unreadable)
    take(0, i);
  for (std::size_t p = 0; p < requests; ++p)
    take(p % byIndex.size(), runs[p % byIndex.size()][p / byIndex.size()]);
  // The runs must be the plan's, in its order: `pbdval run --shard` records the whole plan's
  // runsDigest in every shard (metadata.planDigest); a run relabelled (another engine, method,
  // case or assignments), swapped with another or edited out of order changes the digest of the
  // merged runs. (Shards of `pbdval sweep` record none: the sweep compares its own plan.)
  const std::string& recorded = first.results.metadata.planDigest;
  for (const ShardResults& s : shards)
    if (s.results.metadata.planDigest != recorded)
      throw std::invalid_argument(s.folder + ": metadata.planDigest " +
                                  s.results.metadata.planDigest + " differs from " + first.folder +
                                  "'s " + recorded + " (shards of different plans)");
  if (!recorded.empty()) {
    const std::string fromRuns = planDigestOfRuns(merged.runs);
    if (fromRuns != recorded)
      throw std::invalid_argument(
          "the shards' runs, merged in plan order, are not the plan they were run from "
          "(metadata.planDigest " +
          recorded + ", the runs give " + fromRuns +
          "): a run was relabelled, reordered or edited in a shard's results.json");
  }
  for (const ShardResults& s : shards)
    for (const auto& [name, data] : s.results.cases) {
      const auto [it, added] = merged.cases.emplace(name, data);
      // Shards run at different times may have read different versions of a case file.
      if (!added && it->second.fileSha256 != data.fileSha256)
        throw std::invalid_argument(s.folder + ": case " + name + " was run from " + data.file +
                                    " with sha256 " + data.fileSha256 + ", another shard from " +
                                    it->second.file + " with sha256 " + it->second.fileSha256 +
                                    " (the case file changed between the shards)");
    }
  return merged;
}

}  // namespace pbdval
