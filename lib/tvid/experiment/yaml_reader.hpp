#pragma once
// Typed, checked access to the YAML tree of an experiment file. Every problem becomes
// one InputError "FILE:LINE: key.path: what is wrong"; a value that was set on the
// command line (`--set key=value`) is reported as coming from "--set".

#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// Where the tree came from: the file, and the key paths overridden on the command line.
class YamlSource {
public:
    YamlSource(std::string file, std::vector<std::string> override_keys)
        : file_(std::move(file)), override_keys_(std::move(override_keys)) {}

    const std::string& file() const { return file_; }

    /// The location of `node` (or, when it has no position, of `fallback`) under key `path`.
    SourceLocation where(const YAML::Node& node, const std::string& path, const YAML::Node& fallback = {}) const;

    [[noreturn]] void fail(const YAML::Node& node, const std::string& path, const std::string& problem,
                           const YAML::Node& fallback = {}) const;

    /// Records the line of the key of an empty value (`key:` with nothing after it):
    /// yaml-cpp places such a null at the next token, often on a later line.
    void note_empty_value(const YAML::Node& value, int key_line) const;

private:
    bool overridden(const std::string& path) const;

    std::string file_;
    std::vector<std::string> override_keys_;
    mutable std::vector<std::pair<YAML::Node, int>> empty_values_;  ///< null value, line of its key
};

/// A scalar read as a number, an integer, a flag or a text; fails with the key path.
double read_number(const YamlSource& src, const YAML::Node& node, const std::string& path);
long long read_integer(const YamlSource& src, const YAML::Node& node, const std::string& path);
bool read_flag(const YamlSource& src, const YAML::Node& node, const std::string& path);
std::string read_text(const YamlSource& src, const YAML::Node& node, const std::string& path);
/// `[a, b]` with a <= b (strictly less when `strict`).
std::pair<double, double> read_interval(const YamlSource& src, const YAML::Node& node, const std::string& path,
                                        bool strict);

/// One of `choices`; otherwise an error listing them.
std::string read_choice(const YamlSource& src, const YAML::Node& node, const std::string& path,
                        std::initializer_list<std::string_view> choices);
std::string read_choice(const YamlSource& src, const YAML::Node& node, const std::string& path,
                        const std::vector<std::string>& choices);

/// A YAML mapping under a dotted key path.
class YamlMap {
public:
    /// Fails unless `node` is a mapping; checks it for duplicate keys.
    YamlMap(const YamlSource& src, YAML::Node node, std::string path);

    const YamlSource& source() const { return *src_; }
    const YAML::Node& node() const { return node_; }
    const std::string& path() const { return path_; }
    std::string key_path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

    bool has(const std::string& key) const;
    /// The value under `key`; an invalid node when absent.
    YAML::Node get(const std::string& key) const;
    /// The keys, in file order.
    std::vector<std::string> keys() const;
    /// Fails on the first key not in `allowed`, suggesting the closest allowed key.
    void allow_only(std::initializer_list<std::string_view> allowed) const;
    void allow_only(const std::vector<std::string>& allowed) const;

    [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
    [[noreturn]] void fail_missing(const std::string& key, const std::string& what = "") const;

    YamlMap map(const std::string& key) const;
    double number(const std::string& key) const;
    std::optional<double> optional_number(const std::string& key) const;
    long long integer(const std::string& key) const;
    bool flag(const std::string& key) const;
    std::string text(const std::string& key) const;
    std::string choice(const std::string& key, std::initializer_list<std::string_view> choices) const;
    std::string choice(const std::string& key, const std::vector<std::string>& choices) const;

private:
    YAML::Node required(const std::string& key) const;

    const YamlSource* src_;
    YAML::Node node_;
    std::string path_;
};

}  // namespace tvid
