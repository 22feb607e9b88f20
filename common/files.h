// common/files.h — output files are written whole or not at all: write to "<path>.tmp" and
// rename over the target, so an error never leaves a half-written result.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>

namespace flexrod {

/// Writes `content` to `path` atomically (temporary + rename). Throws std::runtime_error.
void WriteFileAtomic(const std::string& path, const std::string& content);

/// Creates a directory and its parents if missing. Throws InputError(key, path, ...) on failure.
void EnsureDirectory(const std::string& key, const std::string& path);

}  // namespace flexrod
