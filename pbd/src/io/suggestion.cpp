#include "pbd/io/suggestion.h"

#include <algorithm>
#include <cctype>

namespace pbd {

std::size_t editDistance(const std::string& a, const std::string& b) {
  const auto lower = [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  };
  const std::size_t n = a.size(), m = b.size();
  // d[i][j]: distance between the first i characters of a and the first j of b.
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i)
    d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j)
    d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1])) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[n][m];
}

std::optional<std::string> closestName(const std::string& name,
                                       const std::vector<std::string>& candidates) {
  const std::size_t limit = std::max<std::size_t>(2, name.size() / 3);
  std::optional<std::string> best;
  std::size_t bestDistance = limit + 1;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = editDistance(name, candidate);
    if (distance < bestDistance) {
      bestDistance = distance;
      best = candidate;
    }
  }
  if (best || name.size() < 3) return best;
  // A name cut short ("energy_drift" for "energy_drift_max"): the first that it begins.
  for (const std::string& candidate : candidates)
    if (candidate.size() > name.size() && editDistance(name, candidate.substr(0, name.size())) == 0)
      return candidate;
  return std::nullopt;
}

std::string didYouMean(const std::string& name, const std::vector<std::string>& candidates) {
  const std::optional<std::string> best = closestName(name, candidates);
  return best ? "; did you mean \"" + *best + "\"?" : "";
}

std::string nameList(const std::vector<std::string>& names, const std::string& none) {
  std::string list;
  for (const std::string& n : names)
    list += (list.empty() ? "" : ", ") + n;
  return list.empty() ? none : list;
}

}  // namespace pbd
