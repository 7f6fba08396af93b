// JSON text read strictly: a key repeated in an object and nesting deeper than a configuration's
// are refused (plain parsing keeps the last of repeated keys silently), and every error is a
// std::invalid_argument naming what was read. config.hpp reads configuration files through it.
#pragma once

#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace drill {

using json = nlohmann::json;

/// Deepest nesting of arrays and objects parse_json_text reads: a configuration nests 4 levels
/// (the damping pairs), so deeper text is not one; refusing it at this depth keeps a hostile
/// file (200 000 nested arrays) from costing minutes and a message as long as the file.
inline constexpr int max_json_depth = 64;

/// Parse JSON text, refusing a key repeated in an object (plain parsing keeps the last one
/// silently): std::invalid_argument("<path>.<key>: duplicate key ..."), and nesting deeper than
/// max_json_depth: std::invalid_argument("<what>: JSON nested too deep: ..."), raised by the
/// parser's callback as it opens level max_json_depth + 1 (nothing deeper is read). Syntax errors
/// become std::invalid_argument naming the position. `what` names the text in the messages
/// (e.g. "config", or "--config FILE").
inline json parse_json_text(const std::string& text, const std::string& what = "config") {
  struct Frame {
    std::string path;
    bool array;
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  std::string last_key;
  auto child_path = [&]() -> std::string {
    if (stack.empty()) return "";
    const Frame& f = stack.back();
    if (f.array) return f.path + "[]";
    return f.path.empty() ? last_key : f.path + "." + last_key;
  };
  const json::parser_callback_t cb = [&](int, json::parse_event_t ev, json& parsed) {
    switch (ev) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (stack.size() >= static_cast<std::size_t>(max_json_depth))
          throw std::invalid_argument(what + ": JSON nested too deep: more than " + std::to_string(max_json_depth) +
                                      " levels of arrays and objects (a configuration has 4)");
        stack.push_back({child_path(), ev == json::parse_event_t::array_start, {}});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!stack.empty()) stack.pop_back();
        break;
      case json::parse_event_t::key: {
        const std::string key = parsed.get<std::string>();
        Frame& f = stack.back();
        const std::string field = f.path.empty() ? key : f.path + "." + key;
        if (!f.keys.insert(key).second)
          throw std::invalid_argument(field + ": duplicate key \"" + key + "\" in a JSON object of the " + what);
        last_key = key;
        break;
      }
      case json::parse_event_t::value:
        break;
    }
    return true;
  };
  try {
    return json::parse(text, cb);
  } catch (const json::parse_error& e) {
    // nlohmann's text starts with "[json.exception.parse_error.101] parse error at ...": keep the position
    std::string why = e.what();
    const std::size_t tag = why.find("] ");
    if (why.rfind("[json.exception.", 0) == 0 && tag != std::string::npos) why = why.substr(tag + 2);
    throw std::invalid_argument(what + ": malformed JSON: " + why);
  }
}

}  // namespace drill
