// The grid SDF cache folder is chosen by the command from the environment and passed to the
// library, which reads no environment itself.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "validation/io/cache_folder.h"

namespace pbdval {
namespace {

EnvironmentLookup environment(std::map<std::string, std::string> variables) {
  return [variables = std::move(variables)](const char* name) -> const char* {
    const auto it = variables.find(name);
    return it == variables.end() ? nullptr : it->second.c_str();
  };
}

TEST(CacheFolder, FromTheEnvironmentInOrderOfPrecedence) {
  EXPECT_EQ(sdfCacheFolder(environment(
                {{"PBDVAL_SDF_CACHE", "/tmp/explicit"}, {"XDG_CACHE_HOME", "/tmp/xdg"}})),
            "/tmp/explicit");
  EXPECT_EQ(sdfCacheFolder(environment({{"PBDVAL_SDF_CACHE", ""}, {"HOME", "/home/a"}})),
            "");  // disabled
  EXPECT_EQ(sdfCacheFolder(environment({{"XDG_CACHE_HOME", "/tmp/xdg"}, {"HOME", "/home/a"}})),
            "/tmp/xdg/pbdval");
  EXPECT_EQ(sdfCacheFolder(environment({{"HOME", "/home/someone"}})),
            "/home/someone/.cache/pbdval");
  EXPECT_EQ(sdfCacheFolder(environment({})), "");
}

}  // namespace
}  // namespace pbdval
