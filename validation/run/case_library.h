// Finding cases: files and folders named on the command line, or the repository's cases/.
#pragma once

#include <string>
#include <vector>

namespace pbdval {

/// The default case folder: ./cases when it exists, else the source tree's cases/.
std::string defaultCaseFolder();

/// Expands files and folders (non-recursive: *.json in a folder) into case files, sorted by
/// name within a folder, duplicates removed. Throws std::invalid_argument for a path that does
/// not exist or a file that is not .json.
std::vector<std::string> collectCaseFiles(const std::vector<std::string>& paths);

/// "cases/joint_hinge.json" → "joint_hinge".
std::string caseNameOf(const std::string& path);

/// Splits "a,b,c" (empty items dropped).
std::vector<std::string> splitList(const std::string& text);

}  // namespace pbdval
