#include "tvid/experiment/yaml_reader.hpp"

#include "tvid/util/text.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>

#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

std::vector<std::string> to_strings(std::initializer_list<std::string_view> list) {
    std::vector<std::string> out;
    for (std::string_view s : list) out.emplace_back(s);
    return out;
}

std::string kind_of(const YAML::Node& node) {
    switch (node.Type()) {
        case YAML::NodeType::Map: return "a mapping";
        case YAML::NodeType::Sequence: return "a list";
        case YAML::NodeType::Null: return "nothing";
        case YAML::NodeType::Scalar: return "'" + node.Scalar() + "'";
        default: return "nothing";
    }
}

}  // namespace

bool YamlSource::overridden(const std::string& path) const {
    for (const std::string& key : override_keys_) {
        if (path == key) return true;
        if (path.size() > key.size() && path.compare(0, key.size(), key) == 0 &&
            (path[key.size()] == '.' || path[key.size()] == '['))
            return true;
    }
    return false;
}

SourceLocation YamlSource::where(const YAML::Node& node, const std::string& path, const YAML::Node& fallback) const {
    if (overridden(path)) return SourceLocation{"--set", 0, path};
    int line = 0;
    if (node.IsDefined() && node.IsNull())
        for (const auto& [value, key_line] : empty_values_)
            if (value.is(node)) line = key_line;
    if (line == 0 && node.IsDefined() && !node.Mark().is_null()) line = node.Mark().line + 1;
    if (line == 0 && fallback.IsDefined() && !fallback.Mark().is_null()) line = fallback.Mark().line + 1;
    return SourceLocation{file_, line, path};
}

void YamlSource::note_empty_value(const YAML::Node& value, int key_line) const {
    for (const auto& entry : empty_values_)
        if (entry.first.is(value)) return;
    empty_values_.emplace_back(value, key_line);
}

void YamlSource::fail(const YAML::Node& node, const std::string& path, const std::string& problem,
                      const YAML::Node& fallback) const {
    const SourceLocation at = where(node, path, fallback);
    throw InputError(at.file, at.line, at.key, problem);
}

double read_number(const YamlSource& src, const YAML::Node& node, const std::string& path) {
    if (!node.IsScalar()) src.fail(node, path, "expected a number, got " + kind_of(node));
    const std::string& s = node.Scalar();
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || std::isspace(static_cast<unsigned char>(s.front())))
        src.fail(node, path, "expected a number, got '" + s + "'");
    if (!std::isfinite(v)) src.fail(node, path, "'" + s + "' is not a finite number");
    // ERANGE with a finite result is an underflow ('1e-400' reads as 0 or a subnormal), as
    // in the CSV reader; with HUGE_VAL it is an overflow.
    if (errno == ERANGE && std::abs(v) > 1.0)
        src.fail(node, path, "'" + s + "' is too large for a number (at most about 1.8e308)");
    return v;
}

long long read_integer(const YamlSource& src, const YAML::Node& node, const std::string& path) {
    if (!node.IsScalar()) src.fail(node, path, "expected a whole number, got " + kind_of(node));
    const std::string& s = node.Scalar();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v) || v != std::floor(v) || std::abs(v) > 9e15)
        src.fail(node, path, "expected a whole number, got '" + s + "'");
    return static_cast<long long>(v);
}

bool read_flag(const YamlSource& src, const YAML::Node& node, const std::string& path) {
    if (node.IsScalar()) {
        std::string s = node.Scalar();
        std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (s == "true" || s == "yes" || s == "on") return true;
        if (s == "false" || s == "no" || s == "off") return false;
    }
    src.fail(node, path, "expected true or false, got " + kind_of(node));
}

std::string read_text(const YamlSource& src, const YAML::Node& node, const std::string& path) {
    if (!node.IsScalar() || node.Scalar().empty()) src.fail(node, path, "expected a name, got " + kind_of(node));
    return node.Scalar();
}

std::pair<double, double> read_interval(const YamlSource& src, const YAML::Node& node, const std::string& path,
                                        bool strict) {
    if (!node.IsSequence() || node.size() != 2)
        src.fail(node, path, "expected two numbers [lower, upper], got " + kind_of(node));
    const double a = read_number(src, node[0], path);
    const double b = read_number(src, node[1], path);
    if (strict ? !(a < b) : !(a <= b))
        src.fail(node, path, "[" + node[0].Scalar() + ", " + node[1].Scalar() + "]: the lower end must be " +
                                 (strict ? "below" : "at most") + " the upper end");
    return {a, b};
}

std::string read_choice(const YamlSource& src, const YAML::Node& node, const std::string& path,
                        std::initializer_list<std::string_view> choices) {
    const std::string s = read_text(src, node, path);
    for (std::string_view c : choices)
        if (s == c) return s;
    src.fail(node, path, "'" + s + "' is not one of: " + join_words(to_strings(choices)));
}

std::string read_choice(const YamlSource& src, const YAML::Node& node, const std::string& path,
                        const std::vector<std::string>& choices) {
    const std::string s = read_text(src, node, path);
    for (const std::string& c : choices)
        if (s == c) return s;
    src.fail(node, path, "'" + s + "' is not one of: " + join_words(choices));
}

YamlMap::YamlMap(const YamlSource& src, YAML::Node node, std::string path)
    : src_(&src), node_(std::move(node)), path_(std::move(path)) {
    if (!node_.IsMap()) src.fail(node_, path_, "expected a mapping of keys, got " + kind_of(node_));
    std::set<std::string> seen;
    for (auto it = node_.begin(); it != node_.end(); ++it) {
        if (!it->first.IsScalar()) src.fail(it->first, path_, "a key must be a plain name");
        const std::string& k = it->first.Scalar();
        if (!seen.insert(k).second) src.fail(it->first, key_path(k), "duplicate key (given twice)");
        if (it->second.IsNull() && !it->first.Mark().is_null()) src.note_empty_value(it->second, it->first.Mark().line + 1);
    }
}

bool YamlMap::has(const std::string& key) const { return get(key).IsDefined(); }

YAML::Node YamlMap::get(const std::string& key) const {
    for (auto it = node_.begin(); it != node_.end(); ++it)
        if (it->first.Scalar() == key) return it->second;
    return YAML::Node(YAML::NodeType::Undefined);
}

std::vector<std::string> YamlMap::keys() const {
    std::vector<std::string> out;
    for (auto it = node_.begin(); it != node_.end(); ++it) out.push_back(it->first.Scalar());
    return out;
}

void YamlMap::allow_only(std::initializer_list<std::string_view> allowed) const { allow_only(to_strings(allowed)); }

void YamlMap::allow_only(const std::vector<std::string>& allowed) const {
    for (auto it = node_.begin(); it != node_.end(); ++it) {
        const std::string& k = it->first.Scalar();
        if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
        std::string hint;
        std::size_t best = 3;
        for (const std::string& a : allowed) {
            const std::size_t d = edit_distance(k, a);
            if (d < best) { best = d; hint = a; }
        }
        std::string problem = "unknown key '" + k + "'";
        problem += hint.empty() ? " (valid keys: " + join_words(allowed) + ")" : " (did you mean '" + hint + "'?)";
        src_->fail(it->first, key_path(k), problem);
    }
}

void YamlMap::fail(const std::string& key, const std::string& problem) const {
    src_->fail(get(key), key_path(key), problem, node_);
}

void YamlMap::fail_missing(const std::string& key, const std::string& what) const {
    src_->fail(node_, key_path(key), "missing" + (what.empty() ? std::string() : " " + what));
}

YAML::Node YamlMap::required(const std::string& key) const {
    YAML::Node n = get(key);
    if (!n.IsDefined()) fail_missing(key);
    return n;
}

YamlMap YamlMap::map(const std::string& key) const { return YamlMap(*src_, required(key), key_path(key)); }
double YamlMap::number(const std::string& key) const { return read_number(*src_, required(key), key_path(key)); }
std::optional<double> YamlMap::optional_number(const std::string& key) const {
    if (!has(key)) return std::nullopt;
    return number(key);
}
long long YamlMap::integer(const std::string& key) const { return read_integer(*src_, required(key), key_path(key)); }
bool YamlMap::flag(const std::string& key) const { return read_flag(*src_, required(key), key_path(key)); }
std::string YamlMap::text(const std::string& key) const { return read_text(*src_, required(key), key_path(key)); }
std::string YamlMap::choice(const std::string& key, std::initializer_list<std::string_view> choices) const {
    return read_choice(*src_, required(key), key_path(key), choices);
}

std::string YamlMap::choice(const std::string& key, const std::vector<std::string>& choices) const {
    return read_choice(*src_, required(key), key_path(key), choices);
}

}  // namespace tvid
