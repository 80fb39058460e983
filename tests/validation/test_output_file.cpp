// OutputFile (validation/io/atomic_file.h): regular files are replaced atomically, everything else
// is written in place or refused, never replaced. The device cases run against device nodes made
// in a temporary folder (mknod), so that a wrong implementation cannot destroy /dev/null.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "validation/io/atomic_file.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;

class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/pbdval-output-XXXXXX";
    ASSERT_NE(::mkdtemp(pattern), nullptr);
    folder_ = pattern;
  }
  void TearDown() override { fs::remove_all(folder_); }

  std::string file(const std::string& name) const { return (folder_ / name).string(); }
  static std::string read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  static mode_t typeOf(const std::string& path) {
    struct stat info {};
    EXPECT_EQ(::lstat(path.c_str(), &info), 0) << path;
    return info.st_mode & S_IFMT;
  }
  /// The message of the runtime_error `f` throws ("" if it does not throw).
  template <class F>
  static std::string errorOf(F f) {
    try {
      f();
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
  /// Nothing but `expected` is left in the folder (no temporary file).
  void expectOnlyEntries(std::size_t expected) const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder_))
      ++n;
    EXPECT_EQ(n, expected);
  }

  fs::path folder_;
};

TEST_F(OutputFileTest, NewAndExistingRegularFilesAreReplacedKeepingPermissions) {
  const std::string path = file("a/b/out.txt");
  writeFileAtomically(path, "first\n");
  EXPECT_EQ(read(path), "first\n");
  ASSERT_EQ(::chmod(path.c_str(), 0640), 0);
  writeFileAtomically(path, "second\n");
  EXPECT_EQ(read(path), "second\n");
  struct stat info {};
  ASSERT_EQ(::stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0640u);
  EXPECT_EQ(fs::directory_iterator(folder_ / "a" / "b")->path().filename(), "out.txt");
}

TEST_F(OutputFileTest, UncommittedFileLeavesTheTargetAsItWas) {
  const std::string path = file("out.txt");
  writeFileAtomically(path, "kept\n");
  {
    OutputFile output(path);
    output.stream() << "never committed";
  }
  EXPECT_EQ(read(path), "kept\n");
  expectOnlyEntries(1);
}

TEST_F(OutputFileTest, AScratchFileWithoutFsyncIsStillReplacedAtomically) {
  // Durability::ProcessCrash leaves out the fsync only: the target holds the old content until
  // commit() renames the complete new one over it, and an uncommitted file changes nothing.
  const std::string path = file("run-1.json");
  writeFileAtomically(path, "old\n", Durability::ProcessCrash);
  {
    OutputFile output(path, Durability::ProcessCrash);
    output.stream() << "new\n";
    EXPECT_EQ(read(path), "old\n");
    output.commit();
  }
  EXPECT_EQ(read(path), "new\n");
  {
    OutputFile output(path, Durability::ProcessCrash);
    output.stream() << "never committed";
  }
  EXPECT_EQ(read(path), "new\n");
  expectOnlyEntries(1);
}

TEST_F(OutputFileTest, SymbolicLinkIsFollowedAndStaysALink) {
  const std::string target = file("target.txt"), link = file("link.txt");
  writeFileAtomically(target, "old\n");
  fs::create_symlink("target.txt", link);  // relative: resolved against the link's folder
  writeFileAtomically(link, "new\n");
  EXPECT_EQ(typeOf(link), S_IFLNK);
  EXPECT_EQ(read(target), "new\n");
  // A link to a missing file creates the file at the link's target.
  const std::string dangling = file("dangling.txt");
  fs::create_symlink(file("created.txt"), dangling);
  writeFileAtomically(dangling, "made\n");
  EXPECT_EQ(typeOf(dangling), S_IFLNK);
  EXPECT_EQ(read(file("created.txt")), "made\n");
}

TEST_F(OutputFileTest, FifoIsWrittenInPlace) {
  const std::string fifo = file("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A non-blocking reader first, so that opening the FIFO for writing does not wait.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  writeFileAtomically(fifo, "through the pipe\n");  // fits the pipe buffer (64 KiB)
  char received[64] = {};
  const ssize_t n = ::read(reader, received, sizeof received - 1);
  ::close(reader);
  EXPECT_EQ(std::string(received, n > 0 ? std::size_t(n) : 0), "through the pipe\n");
  EXPECT_EQ(typeOf(fifo), S_IFIFO);
  expectOnlyEntries(1);
}

// Character devices made here with the numbers of /dev/null (1, 3) and /dev/full (1, 7).
TEST_F(OutputFileTest, NullDeviceIsWrittenNotReplaced) {
  const std::string null = file("null");
  if (::mknod(null.c_str(), S_IFCHR | 0666, ::makedev(1, 3)) != 0)
    GTEST_SKIP() << "mknod failed (" << std::strerror(errno) << "): needs root and a file "
                 << "system that allows device nodes";
  writeFileAtomically(null, "discarded\n");
  EXPECT_EQ(typeOf(null), S_IFCHR);
  expectOnlyEntries(1);
}

TEST_F(OutputFileTest, FullDeviceReportsTheWriteError) {
  const std::string full = file("full");
  if (::mknod(full.c_str(), S_IFCHR | 0666, ::makedev(1, 7)) != 0)
    GTEST_SKIP() << "mknod failed (" << std::strerror(errno) << "): needs root and a file "
                 << "system that allows device nodes";
  const std::string message = errorOf([&] { writeFileAtomically(full, "cannot fit\n"); });
  EXPECT_NE(message.find(full), std::string::npos) << message;
  EXPECT_NE(message.find(std::strerror(ENOSPC)), std::string::npos) << message;
  EXPECT_EQ(typeOf(full), S_IFCHR);
  expectOnlyEntries(1);
}

TEST_F(OutputFileTest, FolderIsRefusedWithWhatItIs) {
  const std::string folder = file("results");
  fs::create_directory(folder);
  const std::string message = errorOf([&] { writeFileAtomically(folder, "x"); });
  EXPECT_NE(message.find("is a folder"), std::string::npos) << message;
  EXPECT_TRUE(fs::is_directory(folder));
  EXPECT_TRUE(fs::is_empty(folder));
  expectOnlyEntries(1);
}

TEST_F(OutputFileTest, FileInTheWayOfAFolderIsNamed) {
  writeFileAtomically(file("plain"), "x");
  const std::string message = errorOf([&] { writeFileAtomically(file("plain/out.txt"), "x"); });
  EXPECT_NE(message.find("plain is a regular file, not a folder"), std::string::npos) << message;
}

// /proc refuses new files with ENOENT; the message must say why instead.
TEST_F(OutputFileTest, KernelFileSystemGivesTheRealReason) {
  if (!fs::exists("/proc/self")) GTEST_SKIP() << "no /proc";
  for (const std::string path :
       {"/proc/self/pbdval-test-output", "/proc/version", "/proc/self/no/such/folder.csv"}) {
    const std::string message = errorOf([&] { writeFileAtomically(path, "x"); });
    EXPECT_NE(message.find("proc file system"), std::string::npos) << message;
    EXPECT_EQ(message.find(std::strerror(ENOENT)), std::string::npos) << message;
    EXPECT_EQ(errorOf([&] { checkOutputFile(path); }), message);
  }
  const std::string folder = errorOf([] { createFolders("/proc/self/pbdval-test-folder/x"); });
  EXPECT_NE(folder.find("proc file system"), std::string::npos) << folder;
}

// checkOutputFile: the errors of OutputFile before a long computation, without opening anything
// (a FIFO without a reader would block) and without leaving a file behind.
TEST_F(OutputFileTest, CheckOpensNothing) {
  const std::string fifo = file("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  checkOutputFile(fifo);  // returns at once: no reader exists
  checkOutputFile(file("sub/new.json"));
  EXPECT_TRUE(fs::is_directory(folder_ / "sub"));
  EXPECT_TRUE(fs::is_empty(folder_ / "sub"));
  fs::create_directory(file("results"));
  EXPECT_NE(errorOf([&] { checkOutputFile(file("results")); }).find("is a folder"),
            std::string::npos);
}

}  // namespace
}  // namespace pbdval
