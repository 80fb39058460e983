#include "validation/cli/python_module.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace pbdval::cli {

int execPython(const std::vector<std::string>& argv) {
  if (argv.empty()) return 2;
  if (::access(argv[0].c_str(), X_OK) != 0) {
    std::fprintf(stderr,
                 "pbdval: %s: the project's Python is missing (%s); run scripts/install-deps\n",
                 argv[0].c_str(), std::strerror(errno));
    return 2;
  }
  std::vector<char*> pointers;
  for (const std::string& a : argv)
    pointers.push_back(const_cast<char*>(a.c_str()));
  pointers.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  ::execv(argv[0].c_str(), pointers.data());
  std::fprintf(stderr, "pbdval: could not run %s: %s\n", argv[0].c_str(), std::strerror(errno));
  return 2;
}

}  // namespace pbdval::cli
