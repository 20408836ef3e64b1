#pragma once
// One entry of `model.elements` seen as an ElementSource (model/element_source.hpp): the
// element kinds read their keys through it, and every problem becomes one line
// "FILE:LINE: model.elements[i].key: what is wrong".

#include <set>
#include <string>
#include <utility>

#include "tvid/experiment/yaml_reader.hpp"
#include "tvid/model/element_source.hpp"
#include "tvid/model/network_spec.hpp"

namespace tvid {

class YamlElementSource final : public ElementSource {
public:
    /// `net`: the network read so far (its nodes, parameters and inputs; new inputs are
    /// added to it); `names`: the element names taken so far.
    YamlElementSource(YamlMap entry, NetworkSpec& net, std::set<std::string>& names)
        : m_(std::move(entry)), src_(m_.source()), net_(net), names_(names) {}

    bool has(const std::string& key) const override { return m_.has(key); }
    Field field(const std::string& key) const override;
    bool names_constant(const std::string& key) const override;
    double number(const std::string& key) const override { return m_.number(key); }
    std::string text(const std::string& key) const override { return m_.text(key); }

    int node(const std::string& key) const override;
    std::pair<int, int> between(bool ground_ok) const override;
    std::pair<Field, Field> field_pair(const std::string& key) const override;
    std::string node_name(int node) const override;
    std::vector<std::unique_ptr<ElementSource>> entries(const std::string& key,
                                                        const std::vector<std::string>& allowed) const override;

    int time_input(const std::string& key, const char* what) override;
    int angle_input(const std::string& key) override;
    bool claim_name(const std::string& name) override { return names_.insert(name).second; }

    [[noreturn]] void fail(const std::string& key, const std::string& problem) const override { m_.fail(key, problem); }
    [[noreturn]] void fail_missing(const std::string& key, const std::string& what = "") const override {
        m_.fail_missing(key, what);
    }

private:
    int node_at(const YAML::Node& value, bool ground_ok) const;
    std::string node_names() const;

    YamlMap m_;
    const YamlSource& src_;
    NetworkSpec& net_;
    std::set<std::string>& names_;
};

}  // namespace tvid
