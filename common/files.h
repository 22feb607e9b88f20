// common/files.h — output files are written whole or not at all: write to "<path>.tmp" and
// rename over the target, so an error never leaves a half-written result. Every write is
// checked; a failure is an IoError naming the file and the system's reason. For tests,
// FLEXROD_FAIL_WRITE=N makes the N-th file committed in the process fail as on a full disk.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <string>

namespace flexrod {

/// Writes `content` to `path` atomically (temporary + rename). Throws IoError
/// naming the system's reason and the file ("No space left on device: out/run/summary.json").
void WriteFileAtomic(const std::string& path, const std::string& content);

/// As WriteFileAtomic, and durable (CommitFile): parts and stores of a sweep.
void WriteFileDurable(const std::string& path, const std::string& content);

/// Makes the completely written file `tmp` durable under `path`: fsync, rename, fsync of the
/// directory. Throws IoError (and removes `tmp`) if the rename fails.
void CommitFile(const std::string& tmp, const std::string& path);

/// Creates a directory and its parents if missing. Throws InputError(key, path, ...) on failure.
void EnsureDirectory(const std::string& key, const std::string& path);

/// Bytes a written file's name may grow by: its temporary (".tmp") and a sweep store's companions
/// (".parts", ".summary.csv").
inline constexpr std::size_t kCompanionSuffix = 16;

/// InputError naming `key` if `path` cannot name a file here: a component longer than the file
/// system's NAME_MAX bytes (255; the last one `reserve` bytes less, for the names flexrod derives
/// from it), or the absolute path longer than PATH_MAX with `reserve`. Input and output names are
/// checked with it before any work (the system's "File name too long" came after it).
void CheckPathLength(const std::string& key, const std::string& path, std::size_t reserve = 0);

/// InputError naming `key` unless `dir` is a directory or can be created as one (its nearest
/// existing ancestor is a writable directory). Creates nothing: output locations are checked
/// before the work, and written after it.
void CheckCanCreateDirectory(const std::string& key, const std::string& dir);

/// InputError naming `key` unless `path` can be written as a file: a name the system allows
/// (CheckPathLength), not a symbolic link, directory, FIFO, device or socket (its temporary would
/// be renamed over it), in an existing writable directory. Creates nothing (checked before the
/// work, written after it).
void CheckCanWriteFile(const std::string& key, const std::string& path);

}  // namespace flexrod
