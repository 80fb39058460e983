#include "validation/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace pbdval {

AtomicFileWriter::AtomicFileWriter(std::string path)
    : path_(std::move(path)),
      temporaryPath_(path_ + ".tmp-" + std::to_string(static_cast<long>(::getpid()))) {
  const std::filesystem::path parent = std::filesystem::path(path_).parent_path();
  if (!parent.empty()) createFolders(parent.string());
  stream_.open(temporaryPath_, std::ios::out | std::ios::trunc | std::ios::binary);
  if (!stream_) throw std::runtime_error(path_ + ": cannot write (" + std::strerror(errno) + ")");
}

AtomicFileWriter::~AtomicFileWriter() {
  if (!committed_) {
    stream_.close();
    std::remove(temporaryPath_.c_str());
  }
}

void AtomicFileWriter::commit() {
  stream_.flush();
  const bool ok = static_cast<bool>(stream_);
  stream_.close();
  if (!ok || stream_.fail()) {
    std::remove(temporaryPath_.c_str());
    committed_ = true;
    throw std::runtime_error(path_ + ": write failed (disk full?)");
  }
  if (std::rename(temporaryPath_.c_str(), path_.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporaryPath_.c_str());
    committed_ = true;
    throw std::runtime_error(path_ + ": cannot replace (" + reason + ")");
  }
  committed_ = true;
}

void writeFileAtomically(const std::string& path, const std::string& content) {
  AtomicFileWriter writer(path);
  writer.stream() << content;
  writer.commit();
}

void createFolders(const std::string& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw std::runtime_error(folder + ": cannot create folder (" + error.message() + ")");
}

}  // namespace pbdval
