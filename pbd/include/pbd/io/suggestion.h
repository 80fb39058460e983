// "Did you mean": the one place that finds the known name closest to a misspelt one, for the
// scene loader's unknown keys and for every name the pbdval command line checks (engines,
// methods, --set keys, sweep parameters, metrics).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace pbd {

/// Case-insensitive optimal-string-alignment distance (insertions, deletions, substitutions
/// and adjacent transpositions each cost 1).
std::size_t editDistance(const std::string& a, const std::string& b);

/// The candidate closest to `name` within an edit distance of max(2, |name| / 3) (so short
/// names get typo-sized suggestions and long ones a little more), the first on ties; else the
/// first candidate that begins with `name` (a name cut short, 3 characters or more); nullopt
/// when there is none. A candidate equal to `name` ignoring case is the closest.
std::optional<std::string> closestName(const std::string& name,
                                       const std::vector<std::string>& candidates);

/// "; did you mean \"X\"?" for the closest candidate, or "" when none is close.
std::string didYouMean(const std::string& name, const std::vector<std::string>& candidates);

/// "a, b, c" (or `none` when empty): the accepted names, for the same messages.
std::string nameList(const std::vector<std::string>& names, const std::string& none = "none");

}  // namespace pbd
