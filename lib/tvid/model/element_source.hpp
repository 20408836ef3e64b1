#pragma once
// What an element kind reads its spec from: one element's entry of the experiment file,
// seen through this interface so that the kinds (on the model floor) know nothing of
// YAML. The experiment floor implements it (experiment/model_reader.cpp). Every
// problem is reported by fail(): one line "FILE:LINE: key.path: what is wrong".

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "tvid/model/field.hpp"

namespace tvid {

class ElementSource {
public:
    virtual ~ElementSource() = default;

    /// Whether the entry gives `key`.
    virtual bool has(const std::string& key) const = 0;
    /// A number or a declared parameter's name; fails when absent.
    virtual Field field(const std::string& key) const = 0;
    Field field_or(const std::string& key, const Field& fallback) const { return has(key) ? field(key) : fallback; }
    /// Whether the value at `key` is a number or a declared parameter (not a channel's name).
    virtual bool names_constant(const std::string& key) const = 0;
    /// A plain number (not a parameter); fails when absent.
    virtual double number(const std::string& key) const = 0;
    virtual std::string text(const std::string& key) const = 0;

    /// `key: [a, b]`, each a number or a declared parameter; fails unless a list of two.
    virtual std::pair<Field, Field> field_pair(const std::string& key) const = 0;

    /// The node named at `key` (not ground); fails when absent or unknown.
    virtual int node(const std::string& key) const = 0;
    /// `between: [a, b]`, `[a]` or `[a, ground]` (the last two only when `ground_ok`).
    virtual std::pair<int, int> between(bool ground_ok) const = 0;
    /// The entries of the list of mappings at `key` (a multi-stage spring's `stages`), each a
    /// source of its own whose keys are limited to `allowed` and whose problems name
    /// `key[i].subkey`; fails when the value is absent or not a non-empty list of mappings.
    virtual std::vector<std::unique_ptr<ElementSource>> entries(const std::string& key,
                                                                const std::vector<std::string>& allowed) const = 0;
    /// A node's name, for messages.
    virtual std::string node_name(int node) const = 0;

    /// The input by time named at `key` (added to the model's inputs when new); `what` says
    /// what the channel is ("a torque", "a speed").
    virtual int time_input(const std::string& key, const char* what) = 0;
    /// The input by crank angle named at `key` (a cylinder pressure), added when new.
    virtual int angle_input(const std::string& key) = 0;
    /// Claims a further element name (a composite's parts); false if it is taken.
    virtual bool claim_name(const std::string& name) = 0;

    [[noreturn]] virtual void fail(const std::string& key, const std::string& problem) const = 0;
    [[noreturn]] virtual void fail_missing(const std::string& key, const std::string& what = "") const = 0;
};

}  // namespace tvid
