// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/files.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "common/error.h"

namespace flexrod {

namespace {

void FsyncPath(const std::string& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) return;  // best effort: a file system without fsync still gets rename atomicity
  (void)::fsync(fd);
  ::close(fd);
}

}  // namespace

namespace {

/// Writes `content` to `tmp` (fwrite and fclose checked); IoError naming `path` otherwise.
void WriteTemporary(const std::string& tmp, const std::string& content, const std::string& path) {
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) throw IoError(std::string(std::strerror(errno)) + ": " + tmp);
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const int write_errno = errno;
  // fclose flushes the buffer: on a full disk the error may surface only here.
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed) {
    const int e = !written ? write_errno : errno;
    std::remove(tmp.c_str());
    throw IoError(std::string(std::strerror(e)) + ": " + path);
  }
}

/// FLEXROD_FAIL_WRITE=N: the N-th file committed in this process fails as on a full disk
/// (fault injection for the tests of what survives a failed write).
void InjectedFault(const std::string& tmp, const std::string& path) {
  static const long fail_at = [] {
    const char* env = std::getenv("FLEXROD_FAIL_WRITE");
    return env ? std::atol(env) : 0L;
  }();
  static std::atomic<long> count{0};
  if (fail_at > 0 && ++count == fail_at) {
    std::remove(tmp.c_str());
    throw IoError(std::string(std::strerror(ENOSPC)) + ": " + path);
  }
}

}  // namespace

namespace {

/// IoError (the temporary removed) if `path` exists and is not a regular file: renaming over it
/// would replace a FIFO, a device or a link (checked again at the write, after the up-front
/// CheckCanWriteFile).
void RefuseToReplace(const std::string& tmp, const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    fs::remove(tmp, ec);
    throw IoError(path + " is not a regular file (a FIFO, device, socket or link): not replaced");
  }
}

}  // namespace

void WriteFileAtomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  WriteTemporary(tmp, content, path);
  InjectedFault(tmp, path);
  RefuseToReplace(tmp, path);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    throw IoError("cannot rename " + tmp + " to " + path + ": " + std::strerror(e));
  }
}

void WriteFileDurable(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  WriteTemporary(tmp, content, path);
  CommitFile(tmp, path);
}

void CommitFile(const std::string& tmp, const std::string& path) {
  InjectedFault(tmp, path);
  RefuseToReplace(tmp, path);
  FsyncPath(tmp, false);
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw IoError("cannot rename " + tmp + " to " + path + ": " + ec.message());
  }
  const std::string dir = std::filesystem::path(path).parent_path().string();
  FsyncPath(dir.empty() ? "." : dir, true);
}

void EnsureDirectory(const std::string& key, const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec || !std::filesystem::is_directory(path)) {
    throw InputError(key, path, "cannot create this directory: " + ec.message());
  }
}

void CheckPathLength(const std::string& key, const std::string& path, std::size_t reserve) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path abs = fs::absolute(path, ec);
  const std::string& whole = ec ? path : abs.native();
  if (whole.size() + reserve >= PATH_MAX) {
    throw InputError(key, path,
                     "is " + std::to_string(whole.size()) +
                         " bytes long as an absolute path; the "
                         "system allows " +
                         std::to_string(PATH_MAX - 1 - reserve) + " here");
  }
  const fs::path name = fs::path(path).filename();
  for (const fs::path& part : fs::path(whole)) {
    const std::size_t limit = NAME_MAX - (part == name ? reserve : 0);
    if (part.native().size() > limit) {
      throw InputError(key, path,
                       "has a name of " + std::to_string(part.native().size()) +
                           " bytes; the file system allows " + std::to_string(limit) + " here");
    }
  }
}

void CheckCanWriteFile(const std::string& key, const std::string& path) {
  namespace fs = std::filesystem;
  CheckPathLength(key, path, kCompanionSuffix);
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(path, ec))) {
    throw InputError(key, path,
                     "is a symbolic link: flexrod writes a temporary beside its output and renames "
                     "it over it, which would replace the link (/dev/stdout is one); give the "
                     "target's path");
  }
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) throw InputError(key, path, "is a directory, not a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    throw InputError(key, path,
                     "is a FIFO, device or socket, not a regular file: flexrod writes a temporary "
                     "beside its output and renames it over it, which would replace it");
  }
  const fs::path parent = fs::absolute(path, ec).parent_path();
  if (fs::exists(parent, ec) && !fs::is_directory(parent, ec)) {
    throw InputError(key, path, "its directory " + parent.string() + " is a file");
  }
  if (!fs::is_directory(parent, ec)) {
    throw InputError(key, path, "its directory " + parent.string() + " does not exist");
  }
  if (::access(parent.c_str(), W_OK) != 0) {
    throw InputError(key, path, "its directory " + parent.string() + " is not writable");
  }
}

void CheckCanCreateDirectory(const std::string& key, const std::string& dir) {
  namespace fs = std::filesystem;
  CheckPathLength(key, dir);
  std::error_code ec;
  fs::path p = fs::absolute(dir, ec);
  if (ec) throw InputError(key, dir, "is not a usable path: " + ec.message());
  while (!fs::exists(p, ec) && p.has_parent_path() && p.parent_path() != p) p = p.parent_path();
  if (!fs::is_directory(p, ec)) {
    throw InputError(key, dir, "cannot be a directory: " + p.string() + " is not a directory");
  }
  if (::access(p.c_str(), W_OK) != 0) {
    throw InputError(key, dir, "cannot be created or written: " + p.string() + " is not writable");
  }
}

}  // namespace flexrod
