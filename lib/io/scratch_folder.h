#pragma once
// A private folder under the system's temporary directory ($TMPDIR), removed with everything in
// it when the object goes: for files a step writes only to read back or to throw away.
#include <filesystem>
#include <string>

namespace vrv {

class ScratchFolder {
 public:
  // Creates TMPDIR/PREFIX-XXXXXX (mkdtemp); throws std::runtime_error naming it and `purpose`
  // when it cannot.
  ScratchFolder(const std::string& prefix, const std::string& purpose);
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path file(const std::string& name) const { return dir_ / name; }

 private:
  std::filesystem::path dir_;
};

}  // namespace vrv
