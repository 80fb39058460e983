// Result files are written atomically: to a temporary file beside the target, then renamed
// over it, so a crash or an interrupted run never leaves a half-written file behind.
#pragma once

#include <fstream>
#include <string>

namespace pbdval {

/// Streams into `<path>.tmp-<pid>`; commit() flushes and renames it to `path`. Destroyed
/// without commit(), it removes the temporary file. Throws std::runtime_error naming the file
/// on any I/O failure.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::string path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  std::ostream& stream() { return stream_; }
  void commit();

 private:
  std::string path_;
  std::string temporaryPath_;
  std::ofstream stream_;
  bool committed_ = false;
};

/// Writes `content` to `path` atomically (creating parent folders).
void writeFileAtomically(const std::string& path, const std::string& content);

/// Creates `folder` and its parents; throws std::runtime_error naming it on failure.
void createFolders(const std::string& folder);

}  // namespace pbdval
