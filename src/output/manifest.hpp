#pragma once
// The manifest of a run's output directory (.fibrane-manifest): every file the run created there, one
// path per line relative to the directory, after a header line. A file is listed (one appended line,
// like a history row) before it is first created, so a killed run's manifest lists all its files. The
// next new run into the directory removes exactly the listed files (and the temporaries of atomic writes
// to them) before it writes its own.
#include <set>
#include <string>
#include <vector>

namespace fibrane::output {

// The name of the manifest file in a run's output directory.
inline constexpr const char* kManifestFile = ".fibrane-manifest";

// Reads the manifest of `directory`: the listed paths, or nothing if it has none. InputError naming the
// manifest (and the line) if it is not a regular file, is larger than 256 MiB, has another header, or lists
// a path that is not a file name or vtk/<name> or interaction/<name> (absolute, "..", other folders).
std::vector<std::string> read_manifest(const std::string& directory);

// Removes the listed files of `directory`: only regular files (a symbolic link or anything else at a
// listed name is left), never through a link (vtk/ and interaction/ must be real directories; the caller
// checks), and the temporaries `<listed>.tmp.<pid>.<n>` that a killed atomic write leaves. With
// `temporaries_only` (a restart, which keeps the run's files) only the temporaries.
void remove_listed_files(const std::string& directory, const std::vector<std::string>& listed,
                         bool temporaries_only = false);

// The manifest a run writes.
class Manifest {
 public:
  // Starts the manifest of `directory` listing `listed` (a restart passes the earlier manifest's paths),
  // replacing any earlier one atomically.
  Manifest(std::string directory, const std::vector<std::string>& listed);
  ~Manifest();
  Manifest(const Manifest&) = delete;
  Manifest& operator=(const Manifest&) = delete;

  // Lists `relative_path` (once) before the caller creates it.
  void add(const std::string& relative_path);
  const std::set<std::string>& files() const { return files_; }

 private:
  std::string path_;
  std::set<std::string> files_;
  int fd_ = -1;
};

}  // namespace fibrane::output
