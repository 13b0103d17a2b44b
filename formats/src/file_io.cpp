#include "annex/formats/file_io.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "annex/formats/haptic_format.h"

namespace annex {
namespace {

Error file_error(const std::filesystem::path& path, std::string_view what, int err) {
  return Error{std::string(what) + " '" + path.string() + "': " + std::strerror(err), Location{}};
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

std::string too_big(const std::filesystem::path& path, unsigned long long size,
                    std::size_t max_bytes) {
  std::string out(1, '\'');
  out += path.string();
  return out + "' is " + std::to_string(size) + " bytes, more than the limit of " +
         std::to_string(max_bytes) + " bytes";
}

}  // namespace

std::string Diagnostic::format() const {
  std::string out;
  if (!location.origin.empty()) {
    out += location.origin;
    if (location.line > 0) {
      out += ':' + std::to_string(location.line);
      if (location.column > 0) out += ':' + std::to_string(location.column);
    }
    out += ": ";
  }
  out += "warning: " + message;
  return out;
}

Result<std::string> read_text_file(const std::filesystem::path& path, std::size_t max_bytes) {
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) return file_error(path, "cannot open", errno);
  struct stat st {};
  if (::fstat(::fileno(file.get()), &st) != 0) return file_error(path, "cannot read", errno);
  if (S_ISDIR(st.st_mode)) return file_error(path, "cannot read", EISDIR);
  // Check the size before reading; pipes and devices report 0 and are capped below.
  if (S_ISREG(st.st_mode) && static_cast<unsigned long long>(st.st_size) > max_bytes)
    return Error{too_big(path, static_cast<unsigned long long>(st.st_size), max_bytes), {}};
  std::string text;
  if (S_ISREG(st.st_mode)) text.reserve(static_cast<std::size_t>(st.st_size));
  char buf[1 << 16];
  for (;;) {
    const std::size_t n = std::fread(buf, 1, sizeof buf, file.get());
    text.append(buf, n);
    if (text.size() > max_bytes)
      return Error{too_big(path, text.size(), max_bytes) + " (or more)", {}};
    if (n < sizeof buf) {
      if (std::ferror(file.get())) return file_error(path, "cannot read", errno);
      break;
    }
  }
  return text;
}

std::string temporary_prefix(const std::filesystem::path& path) {
  return "." + path.filename().string() + ".tmp-";
}

Status write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  const std::filesystem::path dir =
      path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::string tmpl = (dir / (temporary_prefix(path) + "XXXXXX")).string();
  const int fd = ::mkstemp(tmpl.data());
  // Messages name the file the user asked for, not the temporary one beside it.
  if (fd < 0) return file_error(path, "cannot write", errno);
  // The temporary is locked until it is renamed or removed, through a second
  // descriptor of the same open file (fclose below closes the first): while the lock
  // is held, remove_stale_temporaries leaves it alone. The lock goes with the process.
  const int lock_fd = ::dup(fd);
  if (lock_fd >= 0) ::flock(lock_fd, LOCK_EX);
  const std::filesystem::path tmp = tmpl;
  const auto release = [&] {
    if (lock_fd >= 0) ::close(lock_fd);
  };
  const auto fail = [&](std::string_view what) {
    const int err = errno;
    ::unlink(tmp.c_str());
    release();
    return Status(file_error(path, what, err));
  };

  // mkstemp makes the file 0600; keep the old file's mode, or use the usual 0644.
  struct stat old {};
  const mode_t mode = ::stat(path.c_str(), &old) == 0 ? (old.st_mode & 07777) : 0644;
  ::fchmod(fd, mode);

  FilePtr file(::fdopen(fd, "wb"));
  if (!file) {
    ::close(fd);
    return fail("cannot write");
  }
  if (std::fwrite(content.data(), 1, content.size(), file.get()) != content.size())
    return fail("cannot write");
  if (std::fflush(file.get()) != 0) return fail("cannot write");
  if (::fsync(::fileno(file.get())) != 0) return fail("cannot sync");
  if (std::fclose(file.release()) != 0) return fail("cannot write");
  if (std::rename(tmp.c_str(), path.c_str()) != 0) return fail("cannot rename");
  release();
  // Make the rename itself durable; a failure here cannot lose the old or new content.
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
  return Ok{};
}

bool is_temporary_of(const std::filesystem::path& candidate, const std::filesystem::path& path) {
  const std::string name = candidate.filename().string();
  const std::string prefix = temporary_prefix(path);
  constexpr std::size_t kSuffix = 6;  // mkstemp's XXXXXX: letters and digits
  if (name.size() != prefix.size() + kSuffix || name.compare(0, prefix.size(), prefix) != 0)
    return false;
  for (std::size_t i = prefix.size(); i < name.size(); ++i) {
    const char c = name[i];
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'))) return false;
  }
  return true;
}

std::vector<std::filesystem::path> remove_stale_temporaries(
    const std::filesystem::path& path, std::filesystem::file_time_type older_than) {
  namespace fs = std::filesystem;
  std::vector<fs::path> removed;
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  fs::directory_iterator it(dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    const fs::path candidate = it->path();
    if (!is_temporary_of(candidate, path)) continue;
    // Not a link or anything but a plain file (O_NOFOLLOW), and written before
    // `older_than`: a save that has just created its temporary and not locked it yet
    // is newer than that.
    const int fd = ::open(candidate.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) continue;
    struct stat st {};
    std::error_code time_ec;
    const auto written = fs::last_write_time(candidate, time_ec);
    const bool stale = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && !time_ec &&
                       written < older_than &&
                       ::flock(fd, LOCK_EX | LOCK_NB) == 0;  // no live save holds it
    if (stale && ::unlink(candidate.c_str()) == 0) removed.push_back(candidate);
    ::close(fd);
  }
  return removed;
}

}  // namespace annex
