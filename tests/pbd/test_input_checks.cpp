// Hostile inputs to the scene loader and the mesh readers: non-UTF-8 bytes, deep nesting,
// paths that are not regular files. Every one gives a SceneError naming the file, whose text is
// valid UTF-8 (so that it can be stored in results.json).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/text_assertions.h"
#include "pbd/io/input_checks.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/io/scene_loader.h"

namespace pbd {
namespace {

using pbd::test::containsAll;

/// True when nlohmann accepts `text` as UTF-8 (dump() throws type_error 316 otherwise).
bool isValidUtf8(const std::string& text) {
  try {
    (void)nlohmann::json(text).dump();
    return true;
  } catch (const nlohmann::json::type_error&) {
    return false;
  }
}

template <class F>
std::string sceneErrorOf(F f) {
  try {
    f();
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no SceneError)";
}

class TemporaryFolder {
 public:
  TemporaryFolder() {
    char pattern[] = "/tmp/pbdval-input-XXXXXX";
    if (::mkdtemp(pattern)) path_ = pattern;
  }
  ~TemporaryFolder() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name, const std::string& content) const {
    const std::string path = path_ + "/" + name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

TEST(PrintableText, EscapesControlAndNonUtf8BytesOnly) {
  EXPECT_EQ(printableText("plain ascii"), "plain ascii");
  EXPECT_EQ(printableText("caf\xC3\xA9 \xE2\x88\x87"
                          "C"),
            "caf\xC3\xA9 \xE2\x88\x87"
            "C");
  EXPECT_EQ(printableText("a\xFF"
                          "b"),
            "a\\xFFb");
  EXPECT_EQ(printableText("tab\there\n"), "tab\\x09here\\x0A");
  EXPECT_EQ(printableText(std::string("nul\0x", 5)), "nul\\x00x");
  // Overlong '/' (C0 AF), a UTF-16 surrogate (ED A0 80), a truncated sequence (E2 88).
  EXPECT_EQ(printableText("\xC0\xAF"), "\\xC0\\xAF");
  EXPECT_EQ(printableText("\xED\xA0\x80"), "\\xED\\xA0\\x80");
  EXPECT_EQ(printableText("\xE2\x88"), "\\xE2\\x88");
}

// nlohmann's parse error quotes the bytes it read last: raw 0xFF in a key.
TEST(HostileScenes, NonUtf8KeyGivesAValidUtf8Message) {
  const std::string message = sceneErrorOf([] { parseScene("{\"Na\xFFme\": 1}", "bad\xFE.json"); });
  EXPECT_TRUE(containsAll(message, {"bad\\xFE.json: ", "invalid JSON", "\\xFF"})) << message;
  EXPECT_TRUE(isValidUtf8(message)) << message;
}

// Long values are shortened to 60 bytes in messages: the cut must not leave half a character.
TEST(HostileScenes, ShortenedValuesStayValidUtf8) {
  std::string accents;
  for (int i = 0; i < 40; ++i)
    accents += "\xC3\xA9";  // é: the 57-byte cut falls on the lead byte of one
  const std::string message =
      sceneErrorOf([&] { parseScene("{\"Name\": [\"" + accents + "\"]}", "cut.json"); });
  EXPECT_TRUE(containsAll(message, {"cut.json: Name: expected a string, got [\"\xC3\xA9", "..."}))
      << message;
  EXPECT_TRUE(isValidUtf8(message)) << message;
}

TEST(HostileScenes, DeepNestingIsRefusedQuicklyNamingTheFile) {
  const auto start = std::chrono::steady_clock::now();
  const std::string deep = "{\"Name\": " + std::string(100000, '[');
  const std::string message = sceneErrorOf([&] { parseScene(deep, "deep.json"); });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(containsAll(message, {"deep.json: Name", "nested deeper than 64 levels"})) << message;
  // The old loader took 20 s here; 64 levels are microseconds. 2 s leaves room for a loaded
  // machine and a sanitizer build.
  EXPECT_LT(seconds, 2.0);
  // Exactly at the limit is accepted by the parser (and fails later, as a string is wanted).
  const std::string atLimit = "{\"Name\": " + std::string(63, '[') + std::string(63, ']') + "}";
  EXPECT_TRUE(containsAll(sceneErrorOf([&] { parseScene(atLimit, "ok.json"); }),
                          {"Name: expected a string"}));
}

TEST(HostileScenes, PathsThatAreNotRegularFilesSayWhatTheyAre) {
  const TemporaryFolder folder;
  EXPECT_TRUE(containsAll(sceneErrorOf([&] { loadScene(folder.path()); }),
                          {folder.path() + ": the scene is a folder, not a file"}));
  EXPECT_TRUE(containsAll(sceneErrorOf([] { loadScene("/dev/null"); }),
                          {"/dev/null: the scene is a character device, not a regular file"}));
  const std::string fifo = folder.path() + "/scene.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Reading a FIFO without a writer would block forever: refused before opening it.
  EXPECT_TRUE(containsAll(sceneErrorOf([&] { loadScene(fifo); }),
                          {"scene.fifo: the scene is a FIFO, not a regular file"}));
  EXPECT_TRUE(containsAll(sceneErrorOf([&] { loadScene(folder.path() + "/missing.json"); }),
                          {"missing.json: cannot open the scene file (No such file"}));
  EXPECT_TRUE(containsAll(sceneErrorOf([&] { loadObj(folder.path()); }),
                          {"the mesh is a folder, not a file"}));
}

TEST(HostileMeshes, BinaryGarbageGivesAValidUtf8Message) {
  const TemporaryFolder folder;
  const std::string obj = folder.file("garbage.obj", "v 0 0 0\n\xFF\xFE\x01garbage 1 2\n");
  const std::string message = sceneErrorOf([&] { loadObj(obj); });
  EXPECT_TRUE(containsAll(message, {"garbage.obj: line 2: unsupported statement '\\xFF\\xFE\\x01"}))
      << message;
  EXPECT_TRUE(isValidUtf8(message)) << message;
  const std::string badNumber = sceneErrorOf([] { parseObj("v 0 \x80 0\n", "n.obj"); });
  EXPECT_TRUE(containsAll(badNumber, {"expected a finite number, got '\\x80'"})) << badNumber;
  EXPECT_TRUE(isValidUtf8(badNumber));
  const std::string tet =
      sceneErrorOf([] { parseTetGen("1 3 0 0\n0 0 0 \xC3\n", "", "t.node", "t.ele"); });
  EXPECT_TRUE(containsAll(tet, {"t.node: line 2", "\\xC3"})) << tet;
  EXPECT_TRUE(isValidUtf8(tet));
}

}  // namespace
}  // namespace pbd
