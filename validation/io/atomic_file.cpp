#include "validation/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <streambuf>
#include <thread>

namespace pbdval {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what);
}

std::string errnoText(int error) {
  return std::strerror(error);
}

// Kernel interface file systems: their files are not storage, and no file can be created in
// them (creating one fails with ENOENT, which would read as "no such folder").
const char* kernelFileSystemName(const std::string& path) {
  struct statfs info {};
  if (::statfs(path.c_str(), &info) != 0) return nullptr;
  switch (static_cast<unsigned long>(info.f_type)) {
    case 0x9fa0UL:  // PROC_SUPER_MAGIC
      return "proc";
    case 0x62656572UL:  // SYSFS_MAGIC
      return "sysfs";
    case 0x64626720UL:  // DEBUGFS_MAGIC
      return "debugfs";
    case 0x27e0ebUL:  // CGROUP_SUPER_MAGIC
      return "cgroup";
    case 0x63677270UL:  // CGROUP2_SUPER_MAGIC
      return "cgroup2";
    case 0x73636673UL:  // SECURITYFS_MAGIC
      return "securityfs";
    default:
      return nullptr;
  }
}

std::string kindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISREG(mode)) return "a regular file";
  return "not a regular file";
}

/// Follows symbolic links (up to 40, as the kernel does) to the path finally written. A link
/// to a missing file resolves to that file's path: it is created there.
std::string followLinks(const std::string& path) {
  fs::path current = path;
  for (int hop = 0; hop < 40; ++hop) {
    struct stat info {};
    if (::lstat(current.c_str(), &info) != 0 || !S_ISLNK(info.st_mode)) return current.string();
    std::error_code error;
    const fs::path target = fs::read_symlink(current, error);
    if (error)
      fail(path,
           "cannot read the symbolic link " + current.string() + " (" + error.message() + ")");
    current = target.is_absolute() ? target : current.parent_path() / target;
  }
  fail(path, "too many levels of symbolic links");
}

}  // namespace

// A stream buffer over a file descriptor that remembers the first write error (errno), so that
// commit() can say why a write failed ("No space left on device").
class OutputFile::Buffer : public std::streambuf {
 public:
  explicit Buffer(int descriptor) : descriptor_(descriptor) {
    setp(data_.data(), data_.data() + data_.size());
  }
  int error() const { return error_; }
  bool drain() { return flushPending(); }

 protected:
  int_type overflow(int_type c) override {
    if (!flushPending()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return flushPending() ? 0 : -1; }

 private:
  bool flushPending() {
    if (error_ != 0) return false;
    const char* next = pbase();
    while (next < pptr()) {
      const ssize_t written = ::write(descriptor_, next, static_cast<std::size_t>(pptr() - next));
      if (written < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
        return false;
      }
      if (written == 0) {
        error_ = EIO;
        return false;
      }
      next += written;
    }
    setp(data_.data(), data_.data() + data_.size());
    return true;
  }

  int descriptor_;
  int error_ = 0;
  std::array<char, 1 << 16> data_{};
};

namespace {

/// The deepest part of `path` that exists ("/proc/self" for "/proc/self/a/b.csv").
std::string nearestExisting(const fs::path& path) {
  for (fs::path p = path; !p.empty(); p = p.parent_path()) {
    struct stat info {};
    if (::stat(p.c_str(), &info) == 0) return p.string();
    if (p == p.parent_path()) break;
  }
  return ".";
}

/// What writing `path` means, decided before anything is opened or created.
struct Plan {
  std::string target;  ///< after following symbolic links
  std::string shown;   ///< for messages: "link (-> target)"
  std::string folder;  ///< where the temporary file goes
  bool exists = false;
  bool direct = false;  ///< a character device or FIFO: written in place
  mode_t mode = 0;
};

Plan planOutput(const std::string& path) {
  if (path.empty()) fail("(empty path)", "expected a file name");
  Plan plan;
  struct stat info {};
  // /dev/stdout, /dev/fd/N, /proc/self/fd/N name an open descriptor (a pipe, a terminal, a
  // redirected file): written through as given, never resolved and replaced.
  for (const char* prefix : {"/dev/stdout", "/dev/stderr", "/dev/fd/", "/proc/self/fd/"}) {
    if (path.rfind(prefix, 0) == 0 && ::stat(path.c_str(), &info) == 0) {
      plan.target = plan.shown = path;
      plan.exists = plan.direct = true;
      plan.mode = info.st_mode;
      if (S_ISDIR(info.st_mode)) fail(path, "is a folder, not a file; give a file name");
      return plan;
    }
  }
  plan.target = followLinks(path);
  plan.shown = plan.target == path ? path : path + " (-> " + plan.target + ")";
  plan.exists = ::stat(plan.target.c_str(), &info) == 0;
  const int statError = plan.exists ? 0 : errno;
  if (statError == ENOTDIR)  // a file where a folder should be: say which
    createFolders(fs::path(plan.target).parent_path().string());
  if (!plan.exists && statError != ENOENT)
    fail(plan.shown, "cannot be written (" + errnoText(statError) + ")");
  plan.mode = info.st_mode;
  if (plan.exists && !S_ISREG(info.st_mode)) {
    // Written in place: renaming a file over /dev/null or a FIFO would replace it.
    plan.direct = S_ISCHR(info.st_mode) || S_ISFIFO(info.st_mode);
    if (!plan.direct)
      fail(plan.shown, "is " + kindOf(info.st_mode) + ", not a file; give a file name");
    return plan;
  }
  const fs::path parent = fs::path(plan.target).parent_path();
  plan.folder = parent.empty() ? "." : parent.string();
  if (const char* kernel =
          kernelFileSystemName(plan.exists ? plan.target : nearestExisting(plan.folder)))
    fail(plan.shown, std::string("is on the ") + kernel +
                         " file system, a kernel interface and not storage: pbdval does not "
                         "write there");
  return plan;
}

/// Opens a FIFO for writing once a reader has it open, waiting at most kFifoReaderWait
/// seconds for one: a plain open() would block for ever when nobody reads. The descriptor is
/// blocking again once open (a reader that is slow is waited for, as with any pipe).
int openFifoWithReader(const std::string& target, const std::string& shown) {
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const int descriptor = ::open(target.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC | O_NONBLOCK);
    if (descriptor >= 0) {
      const int flags = ::fcntl(descriptor, F_GETFL);
      if (flags < 0 || ::fcntl(descriptor, F_SETFL, flags & ~O_NONBLOCK) != 0) {
        const std::string reason = errnoText(errno);
        ::close(descriptor);
        fail(shown, "cannot open a FIFO for writing (" + reason + ")");
      }
      return descriptor;
    }
    if (errno != ENXIO && errno != EINTR)
      fail(shown, "cannot open a FIFO for writing (" + errnoText(errno) + ")");
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (waited >= kFifoReaderWait)
      fail(shown, "is a FIFO that no process reads: nothing opened it for reading within " +
                      std::to_string(static_cast<int>(kFifoReaderWait)) +
                      " s; start the reader first (e.g. cat FIFO &)");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

}  // namespace

void checkOutputFile(const std::string& path) {
  const Plan plan = planOutput(path);
  if (plan.direct) {
    if (::access(plan.target.c_str(), W_OK) != 0)
      fail(plan.shown, "cannot be written (" + errnoText(errno) + ")");
    return;
  }
  createFolders(plan.folder);
  if (::access(plan.folder.c_str(), W_OK) != 0)
    fail(plan.shown,
         "cannot create files in the folder " + plan.folder + " (" + errnoText(errno) + ")");
}

OutputFile::OutputFile(std::string path, Durability durability)
    : path_(std::move(path)), durability_(durability) {
  const Plan plan = planOutput(path_);
  target_ = plan.target;
  const std::string& shown = plan.shown;
  if (plan.direct && S_ISFIFO(plan.mode)) {
    descriptor_ = openFifoWithReader(target_, shown);
  } else if (plan.direct) {
    descriptor_ = ::open(target_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    if (descriptor_ < 0)
      fail(shown, "cannot open " + kindOf(plan.mode) + " for writing (" + errnoText(errno) + ")");
  } else {
    createFolders(plan.folder);
    const std::string base = target_ + ".tmp-" + std::to_string(static_cast<long>(::getpid()));
    for (int attempt = 0; descriptor_ < 0; ++attempt) {
      temporary_ = attempt == 0 ? base : base + "-" + std::to_string(attempt);
      descriptor_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (descriptor_ < 0 && (errno != EEXIST || attempt >= 100)) {
        const std::string reason = errnoText(errno);
        temporary_.clear();
        fail(shown,
             "cannot create a temporary file in the folder " + plan.folder + " (" + reason + ")");
      }
    }
    // A replaced file keeps its permission bits (the temporary one has the umask's).
    if (plan.exists) ::fchmod(descriptor_, plan.mode & 07777);
  }
  buffer_ = std::make_unique<Buffer>(descriptor_);
  stream_ = std::make_unique<std::ostream>(buffer_.get());
}

OutputFile::~OutputFile() {
  if (finished_) return;
  if (descriptor_ >= 0) ::close(descriptor_);
  if (!temporary_.empty()) ::unlink(temporary_.c_str());
}

std::ostream& OutputFile::stream() {
  return *stream_;
}

void OutputFile::commit() {
  if (finished_) fail(path_, "already committed");
  finished_ = true;
  const bool drained = buffer_->drain();
  const int writeError = buffer_->error();
  const bool streamOk = static_cast<bool>(*stream_);
  // fsync only regular files (a device or FIFO may not support it: EINVAL), and only when the
  // file must survive a system crash.
  const bool synced =
      temporary_.empty() || durability_ == Durability::ProcessCrash || ::fsync(descriptor_) == 0;
  const int syncError = synced ? 0 : errno;
  const bool closed = ::close(descriptor_) == 0;
  const int closeError = closed ? 0 : errno;
  descriptor_ = -1;
  std::string problem;
  if (!drained || writeError != 0)
    problem = "write failed (" + errnoText(writeError != 0 ? writeError : EIO) + ")";
  else if (!streamOk)
    problem = "write failed (the output stream reported an error)";
  else if (!synced)
    problem = "write failed (" + errnoText(syncError) + ")";
  else if (!closed)
    problem = "write failed (" + errnoText(closeError) + ")";
  if (!problem.empty()) {
    if (!temporary_.empty()) ::unlink(temporary_.c_str());
    fail(path_, problem + (temporary_.empty() ? "" : "; the file was left as it was"));
  }
  if (temporary_.empty()) return;
  if (::rename(temporary_.c_str(), target_.c_str()) != 0) {
    const std::string reason = errnoText(errno);
    ::unlink(temporary_.c_str());
    fail(path_, "cannot replace (" + reason + ")");
  }
}

namespace {

/// How a path is identified for checkOutputsAreNotInputs: by (device, inode) when it exists,
/// else by its absolute, normalised path; nullopt for what is never replaced (devices, FIFOs).
struct FileIdentity {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  std::string path;
  bool operator==(const FileIdentity& other) const {
    return exists == other.exists &&
           (exists ? device == other.device && inode == other.inode : path == other.path);
  }
};

std::optional<FileIdentity> identityOf(const std::string& path) {
  if (path.empty()) return std::nullopt;
  FileIdentity id;
  // "x/../scene.json" with no folder x: the writer creates x and writes scene.json, so the
  // normalised path is what is written when the path as given cannot be resolved yet.
  std::error_code error;
  std::string normalised = fs::weakly_canonical(fs::absolute(followLinks(path)), error).string();
  if (error) normalised = fs::absolute(path).lexically_normal().string();
  for (const std::string& candidate : {path, normalised}) {
    struct stat info {};
    if (::stat(candidate.c_str(), &info) != 0) continue;
    if (S_ISCHR(info.st_mode) || S_ISFIFO(info.st_mode)) return std::nullopt;
    id.exists = true;
    id.device = info.st_dev;
    id.inode = info.st_ino;
    return id;
  }
  id.path = normalised;
  return id;
}

}  // namespace

void checkOutputsAreNotInputs(const std::vector<NamedPath>& outputs,
                              const std::vector<NamedPath>& inputs) {
  std::vector<std::pair<const NamedPath*, FileIdentity>> seen;
  for (const NamedPath& output : outputs) {
    const std::optional<FileIdentity> id = identityOf(output.second);
    if (!id) continue;
    for (const NamedPath& input : inputs) {
      const std::optional<FileIdentity> other = identityOf(input.second);
      if (other && *other == *id)
        throw std::invalid_argument(
            output.first + " " + output.second + " is " + input.first + " (" + input.second + ")" +
            (output.second == input.second ? "" : " under another name") +
            ": writing it would destroy an input of this command; give another file");
    }
    for (const auto& [earlier, identity] : seen)
      if (identity == *id)
        throw std::invalid_argument(output.first + " " + output.second + " and " + earlier->first +
                                    " " + earlier->second +
                                    " are the same file: one would overwrite the other; give "
                                    "two different files");
    seen.emplace_back(&output, *id);
  }
}

void writeFileAtomically(const std::string& path, const std::string& content,
                         Durability durability) {
  OutputFile file(path, durability);
  file.stream() << content;
  file.commit();
}

void createFolders(const std::string& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (!error) return;
  // Say which part of the path is in the way ("results.json is a regular file").
  fs::path partial;
  for (const fs::path& part : fs::path(folder)) {
    partial /= part;
    struct stat info {};
    if (::stat(partial.c_str(), &info) == 0 && !S_ISDIR(info.st_mode))
      fail(folder, "cannot create folder: " + partial.string() + " is " + kindOf(info.st_mode) +
                       ", not a folder");
  }
  if (const char* kernel = kernelFileSystemName(nearestExisting(folder)))
    fail(folder, std::string("cannot create folder: ") + nearestExisting(folder) + " is on the " +
                     kernel + " file system, a kernel interface and not storage");
  fail(folder, "cannot create folder (" + error.message() + ")");
}

}  // namespace pbdval
