#pragma once
// Scratch folders and files for tests, removed when the folder object goes away.

#include <filesystem>
#include <string>

namespace tvid::test {

/// The repository root (configs/, data/).
std::filesystem::path source_dir();

class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    /// Writes `content` to path()/name and returns the full path.
    std::filesystem::path write(const std::string& name, const std::string& content) const;

private:
    std::filesystem::path path_;
};

std::string read_text(const std::filesystem::path& file);

}  // namespace tvid::test
