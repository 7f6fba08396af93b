// The keys of a configuration block, each declared once: its description and the member it binds to.
//
// A Key<T> is one key of a JSON object: what the JSON Schema says of it (schema::Field: its name,
// JSON type, meaning and unit, the bounds the validators enforce, the default) and the member of T
// it reads into and writes from (a member pointer, a lambda returning the member, or a get/set pair
// for values written as names). A Table<T> is a block of keys, with variants picked by the block's
// "type". Reading a JSON object into a T (Table::read), writing a T back as JSON (Table::write) and
// describing the block for the JSON Schema (Table::block, config_schema.hpp) all run over the same
// list, so a key is declared in one place. config.hpp declares the configuration's tables.
//
// Reading: a present key must have the JSON type of its field ("<path> = <value>: must be a number");
// an absent key is refused when required ("<path>: missing (required number)", unless the validator
// refuses its absence: Field::req_in_validate), otherwise it takes the field's default, or keeps the
// member's own value when the field has none (a default that depends on other keys, set before reading).
// An absent array is empty (a required one is then refused by the validator); absent rows are refused
// with their shape. Bounds are checked by the structs' validate(), which also checks configurations
// built in code, not by the reader (tests/cpp/test_config.cpp checks that the two agree).
// Writing: every key is written, except a number that is not finite (NaN or infinite: the member's,
// or its getter's, way of saying "absent"; JSON has no such number).
#pragma once

#include <nlohmann/json.hpp>
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "drill/names.hpp"

namespace drill {

using json = nlohmann::json;

namespace schema {

/// A bound of a number (the validator's): its value and whether the value itself is refused.
struct Bound {
  double value;
  bool exclusive;
};

/// What the JSON Schema says of one key of a block. `dflt` is the value taken when the key is absent
/// (null: the key is required, or its default depends on other keys as `doc` says).
struct Field {
  enum class Type { number, integer, string, numbers, integers, rows, object, objects };
  std::string key;
  Type type;
  std::string doc;
  json dflt = nullptr;
  bool required = false;             ///< must be present (an array: and not empty)
  bool checked_by_validate = false;  ///< required, but its absence is refused by the struct's validate()
  std::optional<Bound> min, max;     ///< number, integer (arrays of them: each item)
  std::vector<std::string> choices;  ///< string: the accepted values (any string when empty)
  std::string block;                 ///< object, objects: the name of the block describing it
  std::vector<Field> columns;        ///< rows: each row is an array of these values
  std::size_t count = 0;             ///< rows: the number of rows
  std::string shape;                 ///< rows: how they are written, for the reader's message

  Field& req() {
    required = true;
    return *this;
  }
  /// Required, with the absence refused by the validator (the reader leaves the member unset).
  Field& req_in_validate() {
    checked_by_validate = true;
    return req();
  }
  Field& def(json value) {
    dflt = std::move(value);
    return *this;
  }
  Field& above(double v) {
    min = Bound{v, true};
    return *this;
  }
  Field& at_least(double v) {
    min = Bound{v, false};
    return *this;
  }
  Field& below(double v) {
    max = Bound{v, true};
    return *this;
  }
  Field& at_most(double v) {
    max = Bound{v, false};
    return *this;
  }
  Field& positive() { return above(0.0); }
  Field& non_negative() { return at_least(0.0); }
};

inline Field number(std::string key, std::string doc) { return {std::move(key), Field::Type::number, std::move(doc)}; }
inline Field integer(std::string key, std::string doc) { return {std::move(key), Field::Type::integer, std::move(doc)}; }
inline Field numbers(std::string key, std::string doc) { return {std::move(key), Field::Type::numbers, std::move(doc)}; }
inline Field integers(std::string key, std::string doc) {
  return {std::move(key), Field::Type::integers, std::move(doc)};
}
inline Field text(std::string key, std::string doc, std::vector<std::string> choices = {}) {
  Field f{std::move(key), Field::Type::string, std::move(doc)};
  f.choices = std::move(choices);
  return f;
}
inline Field object(std::string key, std::string block, std::string doc) {
  Field f{std::move(key), Field::Type::object, std::move(doc)};
  f.block = std::move(block);
  return f;
}
inline Field objects(std::string key, std::string block, std::string doc) {
  Field f{std::move(key), Field::Type::objects, std::move(doc)};
  f.block = std::move(block);
  return f;
}
/// `count` rows of numbers, each with the `columns`, written as `shape` (e.g. "[[f1_hz, ratio1], ...]").
inline Field rows(std::string key, std::string shape, const std::string& doc, std::size_t count,
                  std::vector<Field> columns) {
  Field f{std::move(key), Field::Type::rows, shape + ": " + doc};
  f.count = count;
  f.columns = std::move(columns);
  f.shape = std::move(shape);
  return f;
}

/// A variant of a block, picked by the block's "type", with the keys it adds.
struct Variant {
  std::string type;
  std::vector<Field> fields;
};

/// A JSON object of the configuration, named as in error messages ("operation"; "string.sections"
/// for each item of that array; "config" for the top level), with its keys and variants.
struct Block {
  std::string name, doc;
  std::vector<Field> fields;      ///< the keys of every variant
  std::vector<Variant> variants;  ///< empty, or one per value of the key "type"
};

}  // namespace schema

namespace detail {

inline void check_keys(const json& j, const std::string& where, const std::set<std::string>& allowed) {
  if (!j.is_object()) throw std::invalid_argument(where + " = " + j.dump() + ": must be a JSON object");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!allowed.count(it.key())) {
      // a key with a control character (a line break...) is shown JSON-escaped: the error stays one line
      const bool plain = std::all_of(it.key().begin(), it.key().end(), [](unsigned char ch) { return ch >= 0x20; });
      const std::string key = plain ? it.key() : json(it.key()).dump();
      throw std::invalid_argument(where + "." + key + " = " + it.value().dump() + ": unknown key");
    }
}

/// An int-ranged JSON integer (a float such as 2.5 or 1e12 is refused, never truncated or wrapped).
inline int checked_int(const json& v, const std::string& field) {
  if (!v.is_number_integer()) throw std::invalid_argument(field + " = " + v.dump() + ": must be an integer");
  const bool in_range = v.is_number_unsigned() ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(INT_MAX)
                                               : v.get<std::int64_t>() >= INT_MIN && v.get<std::int64_t>() <= INT_MAX;
  if (!in_range)
    throw std::invalid_argument(field + " = " + v.dump() + ": out of range (integers are " + std::to_string(INT_MIN) +
                                " to " + std::to_string(INT_MAX) + ")");
  return static_cast<int>(v.get<std::int64_t>());
}

// A JSON value read as the C++ type of the member (`path` names it in the messages).
inline void read_value(const schema::Field&, const json& v, const std::string& path, double& out) {
  if (!v.is_number()) throw std::invalid_argument(path + " = " + v.dump() + ": must be a number");
  out = v.get<double>();
}
inline void read_value(const schema::Field&, const json& v, const std::string& path, int& out) {
  out = checked_int(v, path);
}
inline void read_value(const schema::Field&, const json& v, const std::string& path, long& out) {
  out = checked_int(v, path);
}
inline void read_value(const schema::Field&, const json& v, const std::string& path, std::string& out) {
  if (!v.is_string()) throw std::invalid_argument(path + " = " + v.dump() + ": must be a string");
  out = v.get<std::string>();
}
inline void read_value(const schema::Field&, const json& v, const std::string& path, std::vector<double>& out) {
  if (!v.is_array()) throw std::invalid_argument(path + " = " + v.dump() + ": must be an array of numbers");
  out.clear();
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (!v[k].is_number())
      throw std::invalid_argument(path + "[" + std::to_string(k) + "] = " + v[k].dump() + ": must be a number");
    out.push_back(v[k].get<double>());
  }
}
inline void read_value(const schema::Field&, const json& v, const std::string& path, std::vector<int>& out) {
  if (!v.is_array()) throw std::invalid_argument(path + " = " + v.dump() + ": must be an array of integers");
  out.clear();
  for (std::size_t k = 0; k < v.size(); ++k) out.push_back(checked_int(v[k], path + "[" + std::to_string(k) + "]"));
}
/// Rows of numbers (Field::Type::rows): the JSON itself, once its shape is checked.
inline void read_value(const schema::Field& f, const json& v, const std::string& path, json& out) {
  bool ok = v.is_array() && v.size() == f.count;
  for (std::size_t r = 0; ok && r < v.size(); ++r) {
    ok = v[r].is_array() && v[r].size() == f.columns.size();
    for (std::size_t c = 0; ok && c < v[r].size(); ++c) ok = v[r][c].is_number();
  }
  if (!ok) throw std::invalid_argument(path + " = " + v.dump() + ": must be " + f.shape);
  out = v;
}

/// The field type a member of C++ type V is read as.
template <class V>
schema::Field::Type field_type() {
  using Type = schema::Field::Type;
  if constexpr (std::is_same_v<V, double>) return Type::number;
  else if constexpr (std::is_same_v<V, int> || std::is_same_v<V, long>) return Type::integer;
  else if constexpr (std::is_same_v<V, std::string>) return Type::string;
  else if constexpr (std::is_same_v<V, std::vector<double>>) return Type::numbers;
  else if constexpr (std::is_same_v<V, std::vector<int>>) return Type::integers;
  else {
    static_assert(std::is_same_v<V, json>, "a key binds a double, int, long, string, vector or rows (json)");
    return Type::rows;
  }
}

}  // namespace detail

/// One key of a block of T: its description and the member it binds to.
template <class T>
struct Key {
  schema::Field field;
  std::function<void(T&, const json&, const std::string&)> read;  ///< a JSON value into t; null: not stored
  std::function<json(const T&)> write;                             ///< t's value as JSON; null: not written

  /// Described only: an object whose block the configuration reads and writes itself (config.hpp).
  Key(schema::Field f) : field(std::move(f)) {}

  /// Bound to a member: a member pointer (&Section::length) or a lambda returning it
  /// ([](auto& c) -> auto& { return c.sim.dt; }).
  template <class At>
  Key(schema::Field f, At at) : field(std::move(f)) {
    using V = std::decay_t<std::invoke_result_t<At&, T&>>;
    check_type<V>();
    read = [at, f = field](T& t, const json& v, const std::string& path) {
      V x{};
      detail::read_value(f, v, path, x);
      std::invoke(at, t) = std::move(x);
    };
    write = [at](const T& t) { return json(std::invoke(at, t)); };
  }

  /// Bound through a getter V(const T&) and a setter (T&, const V&) or (T&, const V&, path), for a
  /// member written as a name (an enum) or checked as it is read.
  template <class Get, class Set>
  Key(schema::Field f, Get get, Set set) : field(std::move(f)) {
    using V = std::decay_t<std::invoke_result_t<Get&, const T&>>;
    check_type<V>();
    read = [set, f = field](T& t, const json& v, const std::string& path) {
      V x{};
      detail::read_value(f, v, path, x);
      if constexpr (std::is_invocable_v<Set&, T&, const V&, const std::string&>) set(t, x, path);
      else set(t, x);
    };
    write = [get](const T& t) { return json(get(t)); };
  }

  /// Accepted and type-checked, never stored nor written (free text, the editors' "$schema").
  static Key ignored(schema::Field f) {
    Key k(std::move(f));
    k.read = [f = k.field](T&, const json& v, const std::string& path) {
      std::string s;
      detail::read_value(f, v, path, s);
    };
    return k;
  }

 private:
  template <class V>
  void check_type() const {
    if (detail::field_type<V>() != field.type)
      throw std::logic_error("configuration key " + field.key + ": bound to a member of another type");
  }
};

/// The "type" key of a block whose struct T has kinds listed by name (T::kinds, names.hpp): it picks
/// the block's variant and sets T::kind.
template <class T>
Key<T> kind_key(const std::string& doc) {
  return {schema::text("type", doc, names_of(T::kinds)).req(), [](const T& t) { return T::kind_name(t.kind); },
          [](T& t, const std::string& v) { t.kind = T::parse_kind(v); }};
}

/// The keys of a variant of a block (the block's "type" has this value).
template <class T>
struct Case {
  std::string type;
  std::vector<Key<T>> keys;
};

/// A block of the configuration bound to a struct T: its name (as in error messages), its
/// description, the keys of every variant and, if it has a "type", the keys of each variant.
template <class T>
struct Table {
  std::string name, doc;
  std::vector<Key<T>> keys;
  std::vector<Case<T>> variants;

  /// The block's description for the JSON Schema.
  schema::Block block() const {
    schema::Block b{name, doc, fields(keys), {}};
    for (const Case<T>& c : variants) b.variants.push_back({c.type, fields(c.keys)});
    return b;
  }

  /// Read the JSON object j (named `where` in the messages, e.g. "string.sections[2]") into t:
  /// "type" first (its value picks the variant), then any key the block does not have is refused,
  /// then the keys in their order. Returns the type ("" for a block without variants).
  std::string read(const json& j, const std::string& where, T& t) const {
    std::string type;
    if (!variants.empty()) {
      read_key(key("type"), j, where, t);
      type = j.at("type").get<std::string>();
    }
    const std::vector<const Key<T>*> accepted = keys_of(type);
    std::set<std::string> names;
    for (const Key<T>* k : accepted) names.insert(k->field.key);
    detail::check_keys(j, where, names);
    for (const Key<T>* k : accepted)
      if (k->field.key != "type") read_key(*k, j, where, t);
    return type;
  }

  /// The JSON object of t: every bound key of the block and of t's variant.
  json write(const T& t) const {
    json j = json::object();
    for (const Key<T>& k : keys) write_key(k, t, j);
    if (!variants.empty())
      for (const Key<T>* k : keys_of(j.at("type").get<std::string>())) write_key(*k, t, j);
    return j;
  }

 private:
  static std::vector<schema::Field> fields(const std::vector<Key<T>>& ks) {
    std::vector<schema::Field> out;
    for (const Key<T>& k : ks) out.push_back(k.field);
    return out;
  }

  const Key<T>& key(const std::string& name_) const {
    for (const Key<T>& k : keys)
      if (k.field.key == name_) return k;
    throw std::logic_error("configuration block " + name + " has no key " + name_);
  }

  /// The block's keys, then those of the variant `type`.
  std::vector<const Key<T>*> keys_of(const std::string& type) const {
    std::vector<const Key<T>*> out;
    for (const Key<T>& k : keys) out.push_back(&k);
    for (const Case<T>& c : variants)
      if (c.type == type)
        for (const Key<T>& k : c.keys) out.push_back(&k);
    return out;
  }

  static void read_key(const Key<T>& k, const json& j, const std::string& where, T& t) {
    using Type = schema::Field::Type;
    const schema::Field& f = k.field;
    if (!k.read) return;  // an object: read by the configuration itself
    const std::string path = where + "." + f.key;
    if (j.contains(f.key)) return k.read(t, j.at(f.key), path);
    switch (f.type) {
      case Type::numbers:
      case Type::integers: return k.read(t, json::array(), path);  // absent: empty
      case Type::rows: return k.read(t, json(), path);              // absent: refused with the shape
      default: break;
    }
    if (f.required && !f.checked_by_validate) {
      const char* what = f.type == Type::number ? "number" : f.type == Type::integer ? "integer" : "string";
      throw std::invalid_argument(path + ": missing (required " + what + ")");
    }
    if (!f.dflt.is_null()) k.read(t, f.dflt, path);
  }

  static void write_key(const Key<T>& k, const T& t, json& j) {
    if (!k.write) return;
    json v = k.write(t);
    const bool absent = k.field.type == schema::Field::Type::number && !std::isfinite(v.get<double>());
    if (!absent) j[k.field.key] = std::move(v);
  }
};

}  // namespace drill
