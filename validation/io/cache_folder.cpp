#include "validation/io/cache_folder.h"

#include <filesystem>

namespace pbdval {

std::string sdfCacheFolder(const EnvironmentLookup& lookup) {
  if (const char* explicitFolder = lookup("PBDVAL_SDF_CACHE")) return explicitFolder;
  if (const char* xdg = lookup("XDG_CACHE_HOME"); xdg && *xdg)
    return (std::filesystem::path(xdg) / "pbdval").string();
  if (const char* home = lookup("HOME"); home && *home)
    return (std::filesystem::path(home) / ".cache" / "pbdval").string();
  return "";
}

}  // namespace pbdval
