#pragma once
// Result files that are either the old version or the new one, never half written: the contents go
// to a temporary file next to the target, are flushed to disk, and the temporary is renamed onto the
// target (rename is atomic within a directory on POSIX file systems).
#include <filesystem>
#include <string_view>

namespace vrv {

// Writes `contents` to `path` atomically, replacing any existing file whole.  The temporary is
// `path` + ".tmp.<pid>" in the same directory; it is fsync'ed before the rename and removed on failure.
// The parent directory must exist (the caller creates it).  Throws std::runtime_error with one line,
// "<path>: cannot write: <reason>", on any failure.  Not for concurrent writes to the same path from
// one process (they would share the temporary).
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace vrv
