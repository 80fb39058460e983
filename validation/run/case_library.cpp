#include "validation/run/case_library.h"

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "pbdval/build_info.h"

namespace pbdval {

namespace fs = std::filesystem;

std::string defaultCaseFolder() {
  if (fs::is_directory("cases")) return "cases";
  return std::string(PBDVAL_SOURCE_DIR) + "/cases";
}

std::vector<std::string> collectCaseFiles(const std::vector<std::string>& paths) {
  std::vector<std::string> files;
  for (const std::string& path : paths) {
    if (fs::is_directory(path)) {
      std::vector<std::string> inFolder;
      for (const auto& entry : fs::directory_iterator(path))
        if (entry.is_regular_file() && entry.path().extension() == ".json")
          inFolder.push_back(entry.path().string());
      std::sort(inFolder.begin(), inFolder.end());
      if (inFolder.empty()) throw std::invalid_argument(path + ": no .json cases in this folder");
      files.insert(files.end(), inFolder.begin(), inFolder.end());
    } else if (fs::is_regular_file(path)) {
      if (fs::path(path).extension() != ".json")
        throw std::invalid_argument(path + ": expected a .json scene file");
      files.push_back(path);
    } else {
      throw std::invalid_argument(path + ": no such file or folder");
    }
  }
  std::vector<std::string> unique;
  for (const std::string& f : files)
    if (std::find(unique.begin(), unique.end(), f) == unique.end()) unique.push_back(f);
  return unique;
}

std::string caseNameOf(const std::string& path) {
  return fs::path(path).stem().string();
}

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

}  // namespace pbdval
