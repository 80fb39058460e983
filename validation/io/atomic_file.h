// Every file pbdval writes (results, baselines, CSV, JUnit, Markdown, sweep and distance JSON)
// goes through OutputFile, so every output path is treated the same way (docs/cli.md#output-files):
//
//   - a new or regular file is replaced atomically: written to a temporary file beside it, then
//     renamed over it, so a crash or an interrupted run never leaves a half-written file; an
//     existing file keeps its permission bits;
//   - a symbolic link is followed: its target is written (atomically if regular), the link stays;
//   - a character device (/dev/null, a terminal) or a FIFO is written directly, never
//     replaced, and a write error (/dev/full) is reported; so is an open descriptor named by
//     /dev/stdout, /dev/stderr, /dev/fd/N or /proc/self/fd/N, whatever it is (a pipe, a file);
//   - a FIFO that no process opens for reading within kFifoReaderWait seconds is refused
//     (instead of waiting for a reader for ever);
//   - a folder, a block device, a socket, or a file of a kernel interface file system (/proc,
//     /sys) is refused with what it is;
//   - every error names the file and the real reason (errno text, or what the path is).
#pragma once

#include <memory>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace pbdval {

/// How long OutputFile waits for a reader of a FIFO it is asked to write, in seconds.
inline constexpr double kFifoReaderWait = 5;

/// What a regular file's atomic replacement survives.
enum class Durability {
  /// A system crash (power loss) too: the data is fsync'ed before the rename, so a rename that
  /// reached the disk never shows an empty or partial file. Every file a user reads.
  SystemCrash,
  /// A crashed or interrupted process only (the rename alone; the kernel holds the data): for
  /// scratch files this command reads back and removes itself, which a system crash discards
  /// anyway (a run's result file, handed from its process to the scheduler). Saves an fsync,
  /// 1–2 ms per file on this machine's disk (docs/benchmarks.md#outside-the-stepping).
  ProcessCrash,
};

/// An output file being written. stream() buffers; commit() flushes, checks every write and
/// (for regular files) renames the temporary file into place. Destroyed without commit(), a
/// temporary file is removed and the target is left as it was. Throws std::runtime_error naming
/// the file on any failure, in the constructor (cannot be written) or in commit().
class OutputFile {
 public:
  explicit OutputFile(std::string path, Durability durability = Durability::SystemCrash);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::ostream& stream();
  void commit();
  /// The path given; the file written is its symlink target when it is a link.
  const std::string& path() const { return path_; }

 private:
  class Buffer;
  std::string path_;       ///< as given
  std::string target_;     ///< after following symbolic links
  std::string temporary_;  ///< empty when writing directly (device, FIFO)
  int descriptor_ = -1;
  std::unique_ptr<Buffer> buffer_;
  std::unique_ptr<std::ostream> stream_;
  bool finished_ = false;
  Durability durability_;
};

/// The name existing callers use.
using AtomicFileWriter = OutputFile;

/// Fails now, as OutputFile(path) would, when `path` cannot be written (a folder, /proc, no
/// permission), without opening or creating it (but creating its folders): for commands that
/// compute for minutes before writing. A FIFO is not opened (that would wait for a reader).
void checkOutputFile(const std::string& path);

/// A file a command names, with what it is for messages: {"--out", "scene.csv"},
/// {"the scene", "cases/x.json"}.
using NamedPath = std::pair<std::string, std::string>;

/// Refuses (std::invalid_argument) an output that would overwrite an input of the same command
/// or another of its outputs (`simulate --out` its scene, `--out` and `--particles` one file,
/// `gate --junit` its baseline, ...). Files are compared by device and inode after following
/// symbolic links, so another name of the same file (a link, "./x", "../d/x") is caught; an output
/// that does not exist yet is compared with the other outputs by its absolute, normalised path.
/// Character devices and FIFOs (/dev/null, /dev/stdout into a pipe) are written in place, never
/// replaced, and are not compared. Empty paths are ignored.
void checkOutputsAreNotInputs(const std::vector<NamedPath>& outputs,
                              const std::vector<NamedPath>& inputs);

/// Writes `content` to `path` through OutputFile (creating parent folders).
void writeFileAtomically(const std::string& path, const std::string& content,
                         Durability durability = Durability::SystemCrash);

/// Creates `folder` and its parents; throws std::runtime_error naming it on failure (and, when
/// a part of the path is a file, which part).
void createFolders(const std::string& folder);

}  // namespace pbdval
