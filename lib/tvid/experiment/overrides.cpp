#include "tvid/experiment/overrides.hpp"

#include <cctype>

#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

bool valid_key_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.';
}

std::vector<std::string> split_path(const std::string& key) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
        const std::size_t dot = key.find('.', start);
        parts.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
        if (dot == std::string::npos) break;
        start = dot + 1;
    }
    return parts;
}

bool is_index(const std::string& s) {
    if (s.empty() || s.size() > 9) return false;
    for (char c : s)
        if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    return true;
}

}  // namespace

Override parse_override(const std::string& text) {
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos)
        throw InputError("--set", 0, text, "expected key=value, e.g. --set estimation.pso.iterations=50");
    Override o{text.substr(0, eq), text.substr(eq + 1)};
    bool ok = !o.key.empty() && o.key.front() != '.' && o.key.back() != '.' && o.key.find("..") == std::string::npos;
    for (char c : o.key) ok = ok && valid_key_char(c);
    if (!ok) throw InputError("--set", 0, o.key, "not a key path (names separated by '.', e.g. estimation.pso.seed)");
    return o;
}

void apply_overrides(YAML::Node& root, const std::vector<Override>& overrides) {
    for (const Override& o : overrides) {
        YAML::Node value;
        try {
            value = YAML::Load(o.value);
        } catch (const YAML::Exception& e) {
            throw InputError("--set", 0, o.key, "the value is not valid YAML: " + e.msg);
        }
        if (!value.IsDefined() || value.IsNull()) value = YAML::Node(o.value);
        const std::vector<std::string> parts = split_path(o.key);
        YAML::Node cur;
        cur.reset(root);
        std::string walked;
        for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
            const std::string& seg = parts[i];
            walked += (walked.empty() ? "" : ".") + seg;
            if (cur.IsSequence() && is_index(seg)) {
                const std::size_t idx = std::stoul(seg);
                if (idx >= cur.size())
                    throw InputError("--set", 0, o.key, walked + ": the list has only " + std::to_string(cur.size()) +
                                                            " entries");
                YAML::Node next = cur[idx];
                cur.reset(next);
                continue;
            }
            if (!cur.IsMap() && !cur.IsNull())
                throw InputError("--set", 0, o.key, walked + " is not a section of keys");
            if (!cur[seg].IsDefined() || cur[seg].IsNull()) cur[seg] = YAML::Node(YAML::NodeType::Map);
            YAML::Node next = cur[seg];
            cur.reset(next);
        }
        const std::string& last = parts.back();
        if (cur.IsSequence() && is_index(last)) {
            const std::size_t idx = std::stoul(last);
            if (idx >= cur.size())
                throw InputError("--set", 0, o.key, "the list has only " + std::to_string(cur.size()) + " entries");
            cur[idx] = value;
        } else if (cur.IsMap() || cur.IsNull()) {
            cur[last] = value;
        } else {
            throw InputError("--set", 0, o.key, "the parent of '" + last + "' is not a section of keys");
        }
    }
}

std::vector<Override> parse_overrides(const std::vector<std::string>& texts) {
    std::vector<Override> out;
    for (const std::string& t : texts) out.push_back(parse_override(t));
    return out;
}

}  // namespace tvid
