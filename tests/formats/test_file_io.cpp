#include "annex/formats/file_io.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>

#include <filesystem>
#include <fstream>
#include <string>

#include "annex/formats/haptic_format.h"
#include "annex/formats/scene_format.h"
#include "../unique_temp_dir.h"
#include "format_test_util.h"

namespace annex {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test under the system temp dir, removed afterwards.
class FileIo : public ::testing::Test {
 protected:
  int entries() const {
    return static_cast<int>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  const test::TempDir tmp_{"formats_file_io"};
  const fs::path dir_ = tmp_.path();
};

TEST_F(FileIo, MissingFileNamesThePath) {
  const fs::path p = dir_ / "nope.haptic";
  auto r = read_text_file(p);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "cannot open '" + p.string() + "': No such file or directory");
  auto h = read_haptic_file(p);
  ASSERT_FALSE(h.ok());
  EXPECT_EQ(h.error().format(),
            "error: cannot open '" + p.string() + "': No such file or directory");
}

TEST_F(FileIo, DirectoryIsRefused) {
  auto r = read_text_file(dir_);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "cannot read '" + dir_.string() + "': Is a directory");
}

TEST_F(FileIo, SizeLimitIsCheckedBeforeReading) {
  const fs::path p = dir_ / "big.txt";
  std::ofstream(p) << std::string(100, 'x');
  auto r = read_text_file(p, 99);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message,
            "'" + p.string() + "' is 100 bytes, more than the limit of 99 bytes");
  auto ok = read_text_file(p, 100);
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(ok->size(), 100u);
}

TEST_F(FileIo, AtomicWriteReplacesContentAndLeavesNoTemporary) {
  const fs::path p = dir_ / "a.txt";
  ASSERT_TRUE(write_file_atomically(p, "first\n").ok());
  EXPECT_EQ(test::slurp(p), "first\n");
  ::chmod(p.c_str(), 0640);
  ASSERT_TRUE(write_file_atomically(p, "second\n").ok());
  EXPECT_EQ(test::slurp(p), "second\n");
  EXPECT_EQ(entries(), 1);
  EXPECT_EQ(fs::status(p).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

TEST_F(FileIo, AtomicWriteFailureKeepsNothingBehind) {
  const fs::path p = dir_ / "missing-dir" / "a.txt";
  auto st = write_file_atomically(p, "x");
  ASSERT_FALSE(st.ok());
  // The message names the file asked for, not the temporary beside it.
  EXPECT_NE(st.error().message.find("cannot write '" + p.string() + "'"), std::string::npos)
      << st.error().message;
  EXPECT_EQ(st.error().message.find(".tmp-"), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find("No such file or directory"), std::string::npos);
  EXPECT_EQ(entries(), 0);

  // Renaming over a directory fails after the temporary was written: it must go away.
  const fs::path target = dir_ / "taken";
  fs::create_directories(target / "child");
  st = write_file_atomically(target, "x");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("cannot rename"), std::string::npos) << st.error().message;
  EXPECT_EQ(entries(), 1);
}

TEST_F(FileIo, StaleTemporariesAreRemovedUnlessLockedOrNewer) {
  const fs::path spec = dir_ / "a.haptic";
  std::ofstream(spec) << "spec\n";
  const auto write = [&](const std::string& name) {
    std::ofstream(dir_ / name) << "partial";
    return dir_ / name;
  };
  const auto start = fs::file_time_type::clock::now();
  const auto before = start - std::chrono::seconds(10);
  const fs::path stale = write(".a.haptic.tmp-Ab12Cd");
  const fs::path held = write(".a.haptic.tmp-held01");
  const fs::path newer = write(".a.haptic.tmp-new001");
  const fs::path other_spec = write(".b.haptic.tmp-Ab12Cd");
  const fs::path short_name = write(".a.haptic.tmp-Ab12C");
  const fs::path odd_char = write(".a.haptic.tmp-Ab_2Cd");
  fs::create_directory(dir_ / ".a.haptic.tmp-dir001");
  fs::create_symlink(spec, dir_ / ".a.haptic.tmp-lnk001");
  for (const fs::path& p : {stale, held, other_spec, short_name, odd_char})
    fs::last_write_time(p, before);
  fs::last_write_time(newer, start + std::chrono::seconds(10));
  EXPECT_TRUE(is_temporary_of(stale, spec));
  EXPECT_FALSE(is_temporary_of(other_spec, spec));
  EXPECT_FALSE(is_temporary_of(short_name, spec));
  EXPECT_FALSE(is_temporary_of(odd_char, spec));

  // A live save holds its temporary's lock (another open file, as in another process).
  const int lock = ::open(held.c_str(), O_RDONLY);
  ASSERT_GE(lock, 0);
  ASSERT_EQ(::flock(lock, LOCK_EX), 0);
  const auto removed = remove_stale_temporaries(spec, start);
  ASSERT_EQ(removed.size(), 1u);
  EXPECT_EQ(removed[0], stale);
  EXPECT_FALSE(fs::exists(stale));
  for (const fs::path& p : {held, newer, other_spec, short_name, odd_char, spec})
    EXPECT_TRUE(fs::exists(p)) << p;
  EXPECT_TRUE(fs::is_directory(dir_ / ".a.haptic.tmp-dir001"));
  EXPECT_TRUE(fs::is_symlink(dir_ / ".a.haptic.tmp-lnk001"));
  EXPECT_EQ(test::slurp(spec), "spec\n");

  // Once the save's process is gone its lock is too, and the file is stale.
  ::close(lock);
  const auto later = remove_stale_temporaries(spec, start);
  ASSERT_EQ(later.size(), 1u);
  EXPECT_EQ(later[0], held);
  EXPECT_TRUE(remove_stale_temporaries(spec, start).empty());
  EXPECT_TRUE(fs::exists(newer));

  // An atomic write leaves nothing of its own behind for the cleaner.
  ASSERT_TRUE(write_file_atomically(spec, "new\n").ok());
  EXPECT_EQ(remove_stale_temporaries(spec, start + std::chrono::hours(1)).size(), 1u);
  EXPECT_FALSE(fs::exists(newer));
  EXPECT_EQ(test::slurp(spec), "new\n");
}

TEST_F(FileIo, HapticAndSceneFilesRoundTrip) {
  auto spec = read_haptic_file(test::data_path("champagne.haptic"));
  ASSERT_TRUE(spec.ok()) << spec.error().format();
  const fs::path hp = dir_ / "out.haptic";
  ASSERT_TRUE(write_haptic_file(hp, *spec).ok());
  EXPECT_EQ(test::slurp(hp), test::slurp(test::data_path("champagne.haptic")));

  auto scene = read_scene_file(test::data_path("kitchen.scene"));
  ASSERT_TRUE(scene.ok()) << scene.error().format();
  const fs::path sp = dir_ / "out.scene";
  ASSERT_TRUE(write_scene_file(sp, *scene).ok());
  EXPECT_EQ(test::slurp(sp), test::slurp(test::data_path("kitchen.scene")));
}

TEST_F(FileIo, WriteHapticFileRefusesAnInvalidSpec) {
  HapticSpec spec;
  VirtualObject o;
  o.name = "x";
  spec.objects.push_back(o);
  const fs::path p = dir_ / "bad.haptic";
  auto st = write_haptic_file(p, spec);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().format(), p.string() +
                                     ": object 'x': error: annexable object 'x' has no "
                                     "primitive; add one or set 'annexable no'");
  EXPECT_FALSE(fs::exists(p));
}

TEST_F(FileIo, ParseErrorsNameTheFile) {
  const fs::path p = dir_ / "e.haptic";
  std::ofstream(p) << "annex-haptic 1\nobject a\n  colour red\n";
  auto r = read_haptic_file(p);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().location, (Location{p.string(), 3, 3}));
}

TEST(Diagnostic, FormatsAsAWarning) {
  EXPECT_EQ((Diagnostic{"careful", Location{"a.haptic", 3, 7}}).format(),
            "a.haptic:3:7: warning: careful");
  EXPECT_EQ((Diagnostic{"careful", Location{"a.haptic", 0, 0}}).format(),
            "a.haptic: warning: careful");
}

}  // namespace
}  // namespace annex
