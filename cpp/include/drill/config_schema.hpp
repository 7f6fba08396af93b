// The JSON Schema (draft 2020-12) of the configuration, for editors: written from the tables of keys
// that parse_config reads and to_json writes (schema::blocks() in config.hpp, config_keys.hpp) with
// their types, units, the validators' bounds and the defaults. Blocks with variants (damping, law, top_drive) select the
// keys of each variant with if/then on their "type". `drillsim --schema` prints it;
// python/drillpy/model/config.schema.json is its copy (scripts/generate-schema.sh). Some checks
// stay with the parser: bounds that relate keys (inner below outer radius, transient below
// duration, modes at most the elements), and a whole number written as 2.0 for an integer.
#pragma once

#include <climits>
#include <string>

#include "drill/config.hpp"

namespace drill {

namespace detail {

/// A number or an integer with the field's bounds (an integer's default bounds: the C int range).
inline json value_schema(const schema::Field& f, bool integer) {
  json s{{"type", integer ? "integer" : "number"}};
  auto value = [&](double v) { return integer ? json(static_cast<long long>(v)) : json(v); };
  if (f.min) s[f.min->exclusive ? "exclusiveMinimum" : "minimum"] = value(f.min->value);
  else if (integer) s["minimum"] = INT_MIN;
  if (f.max) s[f.max->exclusive ? "exclusiveMaximum" : "maximum"] = value(f.max->value);
  else if (integer) s["maximum"] = INT_MAX;
  return s;
}

inline json field_schema(const schema::Field& f) {
  using Type = schema::Field::Type;
  json s;
  switch (f.type) {
    case Type::number: s = value_schema(f, false); break;
    case Type::integer: s = value_schema(f, true); break;
    case Type::string:
      s = {{"type", "string"}};
      if (!f.choices.empty()) s["enum"] = f.choices;
      break;
    case Type::numbers: s = {{"type", "array"}, {"items", value_schema(f, false)}}; break;
    case Type::integers: s = {{"type", "array"}, {"items", value_schema(f, true)}}; break;
    case Type::objects: s = {{"type", "array"}, {"items", {{"$ref", "#/$defs/" + f.block}}}}; break;
    case Type::object: s = {{"$ref", "#/$defs/" + f.block}}; break;
    case Type::rows: {
      json columns = json::array();
      for (const schema::Field& c : f.columns) columns.push_back(field_schema(c));
      s = {{"type", "array"},
           {"minItems", f.count},
           {"maxItems", f.count},
           {"items",
            {{"type", "array"}, {"prefixItems", columns}, {"minItems", f.columns.size()}, {"items", false}}}};
      break;
    }
  }
  if (f.required && (f.type == Type::numbers || f.type == Type::integers || f.type == Type::objects))
    s["minItems"] = 1;
  s["description"] = f.doc;
  if (!f.dflt.is_null()) s["default"] = f.dflt;
  return s;
}

/// An object with the block's keys and nothing else; with variants, an if/then per value of "type"
/// that admits the keys of that variant.
inline json block_schema(const schema::Block& b) {
  json props = json::object(), required = json::array();
  for (const schema::Field& f : b.fields) {
    props[f.key] = field_schema(f);
    if (f.required) required.push_back(f.key);
  }
  json s{{"type", "object"}, {"description", b.doc}, {"properties", props}};
  if (!required.empty()) s["required"] = required;
  if (b.variants.empty()) {
    s["additionalProperties"] = false;
    return s;
  }
  json cases = json::array();
  for (const schema::Variant& v : b.variants) {
    json vprops = json::object(), vrequired = json::array();
    for (const schema::Field& f : b.fields) vprops[f.key] = true;  // described above
    for (const schema::Field& f : v.fields) {
      vprops[f.key] = field_schema(f);
      if (f.required) vrequired.push_back(f.key);
    }
    json then{{"properties", vprops}, {"additionalProperties", false}};
    if (!vrequired.empty()) then["required"] = vrequired;
    cases.push_back({{"if", {{"properties", {{"type", {{"const", v.type}}}}}, {"required", {"type"}}}}, {"then", then}});
  }
  s["allOf"] = cases;
  return s;
}

}  // namespace detail

/// The configuration's JSON Schema (draft 2020-12): the top level, and one $defs entry per block.
inline json config_schema() {
  json out{{"$schema", "https://json-schema.org/draft/2020-12/schema"}, {"title", "drillpy configuration"}};
  json defs = json::object();
  for (const schema::Block& b : schema::blocks()) {
    if (b.name == "config") out.update(detail::block_schema(b));
    else defs[b.name] = detail::block_schema(b);
  }
  out["$defs"] = defs;
  return out;
}

}  // namespace drill
