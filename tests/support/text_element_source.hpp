#pragma once
// An element entry as plain text values for the element kinds' readers
// (model/element_source.hpp), without YAML: the value "p" is parameter 0, the nodes are a
// and b, and fail() throws "key: problem".

#include <algorithm>
#include <functional>
#include <memory>
#include <vector>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "tvid/model/element_reading.hpp"
#include "tvid/model/network_spec.hpp"

namespace tvid::test {

// An element entry as plain text values, with the nodes a, b and the parameter p, and lists
// of such entries (`stages`); fail() throws "key: problem" (in a list "stages[i].key: problem").
class TextSource final : public ElementSource {
public:
    using Values = std::map<std::string, std::string>;
    using Lists = std::map<std::string, std::vector<Values>>;
    explicit TextSource(Values values) : values_(std::move(values)) {}
    /// An entry with lists of entries too (`stages`), its messages prefixed by `prefix`.
    static TextSource with_lists(Values values, Lists lists, std::string prefix = "") {
        TextSource s(std::move(values));
        s.lists_ = std::move(lists);
        s.prefix_ = std::move(prefix);
        return s;
    }
    bool has(const std::string& key) const override { return values_.count(key) > 0; }
    Field field(const std::string& key) const override {
        if (!has(key)) fail_missing(key);
        return values_.at(key) == "p" ? Field::param(0) : Field::value(std::stod(values_.at(key)));
    }
    bool names_constant(const std::string& key) const override { return values_.at(key) != "w"; }
    double number(const std::string& key) const override { return std::stod(values_.at(key)); }
    std::string text(const std::string& key) const override { return values_.at(key); }
    int node(const std::string& key) const override { return values_.at(key) == "a" ? 0 : 1; }
    std::pair<int, int> between(bool) const override { return {0, 1}; }
    /// "lo,hi" (each a number or "p").
    std::pair<Field, Field> field_pair(const std::string& key) const override {
        const std::string text = values_.at(key);
        const auto comma = text.find(',');
        if (comma == std::string::npos) fail(key, "expected [min, max]");
        const auto one = [](const std::string& v) { return v == "p" ? Field::param(0) : Field::value(std::stod(v)); };
        return {one(text.substr(0, comma)), one(text.substr(comma + 1))};
    }
    std::string node_name(int node) const override { return node == 0 ? "a" : "b"; }
    std::vector<std::unique_ptr<ElementSource>> entries(const std::string& key,
                                                        const std::vector<std::string>& allowed) const override {
        if (lists_.count(key) == 0) fail_missing(key);
        std::vector<std::unique_ptr<ElementSource>> out;
        for (std::size_t i = 0; i < lists_.at(key).size(); ++i) {
            const std::string at = key + "[" + std::to_string(i) + "].";
            for (const auto& [k, v] : lists_.at(key)[i])
                if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) fail(at + k, "unknown key");
            out.push_back(std::make_unique<TextSource>(with_lists(lists_.at(key)[i], {}, prefix_ + at)));
        }
        return out;
    }
    int time_input(const std::string&, const char*) override { return 0; }
    int angle_input(const std::string&) override { return 0; }
    bool claim_name(const std::string&) override { return true; }
    [[noreturn]] void fail(const std::string& key, const std::string& problem) const override {
        throw std::runtime_error(prefix_ + key + ": " + problem);
    }
    [[noreturn]] void fail_missing(const std::string& key, const std::string& = "") const override {
        fail(key, "missing");
    }

private:
    Values values_;
    Lists lists_;
    std::string prefix_;
};

inline NetworkSpec two_nodes() {
    NetworkSpec net;
    net.parameter_names = {"p"};
    net.input_names = {"u"};
    net.nodes = {NodeSpec{"a", Field::value(1.0), false}, NodeSpec{"b", Field::value(1.0), false}};
    return net;
}

inline std::string read_error(TextSource source, const std::function<void(TextSource&, NetworkSpec&)>& read) {
    NetworkSpec net = two_nodes();
    try {
        read(source, net);
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

}  // namespace tvid::test
