// Commands whose work is done in Python (the Dask client): run the project's virtual
// environment's interpreter in place of this process.
#pragma once

#include <string>
#include <vector>

namespace pbdval::cli {

/// Replaces this process by `argv` (argv[0]: the interpreter, by path). Returns only when that
/// fails: prints why (naming the interpreter and how to create it) and returns exit status 2.
int execPython(const std::vector<std::string>& argv);

}  // namespace pbdval::cli
