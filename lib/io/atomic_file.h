#pragma once
// Result files that are either the old version or the new one, never half written: the contents go
// to a temporary file next to the target, are flushed to disk, and the temporary is renamed onto the
// target (rename is atomic within a directory on POSIX file systems).
#include <filesystem>
#include <shared_mutex>
#include <string>
#include <string_view>

namespace vrv {

// Writes `contents` to `path` atomically, replacing any existing file whole.  The temporary is
// `path` + temporary_suffix() in the same directory; it is fsync'ed before the rename and removed on
// failure.  The parent directory must exist (the caller creates it).  Throws std::runtime_error with
// one line, "<path>: cannot write: <reason>", on any failure.  Concurrent writers of one path (threads,
// processes, machines sharing the folder) each rename a whole file of their own: the last one wins.
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

// ".tmp.<pid>.<16 random hex digits>": a name no other thread, process or machine uses at once.
std::string temporary_suffix();

// Held shared by write_file_atomically while its temporary exists.  A process stopping on a
// signal takes it exclusively before it removes its temporaries and never releases it, so no
// worker thread can create a temporary after that sweep (studies/engine/interrupt.cpp).
std::shared_mutex& temporary_files_mutex();

}  // namespace vrv
