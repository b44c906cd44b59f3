#include "bouguer/io/json.h"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <string>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"

namespace bouguer {
namespace {

using json = nlohmann::json;

// A pointer into the text that records the last byte the lexer read, so that a SAX event (a key)
// can be placed in the file: nlohmann passes positions to parse_error only.
struct TrackingIterator {
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  const char* at = nullptr;
  const char** last_read = nullptr;

  reference operator*() const {
    *last_read = at;
    return *at;
  }
  TrackingIterator& operator++() {
    ++at;
    return *this;
  }
  TrackingIterator operator++(int) {
    TrackingIterator before = *this;
    ++at;
    return before;
  }
  bool operator==(const TrackingIterator& other) const { return at == other.at; }
};

// The document tree, built as nlohmann's own DOM parser does (a stack of the open containers), with
// the checks it lacks. The first problem stops the parse and is kept as `error`.
class CheckedBuilder : public nlohmann::json_sax<json> {
 public:
  CheckedBuilder(std::string_view text, const std::filesystem::path& file, const char* const& last_read)
      : text_(text), file_(file), last_read_(last_read) {}

  json root;
  std::string error;  // empty when the document was read

  bool null() override { return put(nullptr); }
  bool boolean(bool v) override { return put(v); }
  bool number_integer(number_integer_t v) override { return put(v); }
  bool number_unsigned(number_unsigned_t v) override { return put(v); }
  bool number_float(number_float_t v, const string_t&) override { return put(v); }
  bool string(string_t& v) override { return put(std::move(v)); }
  bool binary(binary_t& v) override { return put(std::move(v)); }

  bool start_object(std::size_t) override { return open(json::object()); }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }

  bool key(string_t& k) override {
    Open& o = open_.back();
    if (o.value->contains(k)) {
      // The lexer has just read the key's closing quote; its opening quote is before the key.
      const auto end = static_cast<std::size_t>(last_read_ - text_.data());
      const std::size_t start = end >= k.size() + 1 ? end - k.size() - 1 : 0;
      error = fmt::format("{}:{}: {}: duplicate key '{}' (each key may appear once in an object)", file_.string(),
                          line_and_column(text_, start), path(false), excerpt(k));
      return false;
    }
    o.key = k;
    pending_ = &(*o.value)[k];
    return true;
  }

  bool parse_error(std::size_t position, const std::string& last_token, const nlohmann::detail::exception& e) override {
    const std::size_t end = std::min(position, text_.size());
    if (e.id == 406) {  // out_of_range: a number that does not fit a double, such as 1e999
      const std::size_t start = end >= last_token.size() ? end - last_token.size() : 0;
      error = fmt::format("{}:{}: the number {} is beyond the range of a double (about ±1.8e308)", file_.string(),
                          line_and_column(text_, start), excerpt(last_token));
      return false;
    }
    error = fmt::format("{}:{}: malformed JSON: {}", file_.string(), line_and_column(text_, end == 0 ? 0 : end - 1),
                        description(e.what(), last_token));
    return false;
  }

 private:
  struct Open {
    json* value;
    std::string key;  // objects: the key being read
  };

  // Where the next value goes: the root, the pending key of an object, or the end of an array.
  json* slot() {
    if (open_.empty()) return &root;
    json& container = *open_.back().value;
    if (container.is_object()) return pending_;
    container.push_back(nullptr);
    return &container.back();
  }

  template <typename V>
  bool put(V&& v) {
    *slot() = json(std::forward<V>(v));
    return true;
  }

  bool open(json&& container) {
    if (open_.size() >= kMaxJsonDepth) {
      const auto at = static_cast<std::size_t>(last_read_ - text_.data());
      error = fmt::format("{}:{}: {}: nested deeper than {} levels", file_.string(), line_and_column(text_, at), path(),
                          kMaxJsonDepth);
      return false;
    }
    json* s = slot();
    *s = std::move(container);
    open_.push_back({s, {}});
    return true;
  }

  bool close() {
    open_.pop_back();
    return true;
  }

  // The key path of the value being read, as the loader's messages write it: objects[2].shape
  // (without the innermost object's last key: the object that holds a duplicate). Cut short when
  // a deep document makes it long.
  std::string path(bool with_last_key = true) const {
    std::string p;
    for (const Open& o : open_) {
      if (&o == &open_.back() && !with_last_key) break;
      if (o.value->is_array()) {
        if (!o.value->empty()) p += fmt::format("[{}]", o.value->size() - 1);
      } else if (!o.key.empty()) {
        if (!p.empty()) p += '.';
        p += excerpt(o.key);
      }
    }
    return p.empty() ? "(top level)" : excerpt(p, 120);
  }

  // nlohmann's message without its prefix and position (given as file:line:column instead), with
  // the token it quotes cut short: "syntax error while parsing value - invalid literal; last read: 'tru'".
  static std::string description(std::string message, const std::string& last_token) {
    if (const auto p = message.find("parse error"); p != std::string::npos) message.erase(0, p);
    if (const auto p = message.find(": "); p != std::string::npos && message.compare(0, 11, "parse error") == 0)
      message.erase(0, p + 2);
    const std::string lead = "; last read: '";
    if (const auto a = message.find(lead); a != std::string::npos) {
      auto b = message.rfind("'; expected ");
      if (b == std::string::npos || b < a + lead.size()) b = message.rfind('\'');
      if (b != std::string::npos && b >= a + lead.size())
        message.replace(a + lead.size(), b - a - lead.size(), excerpt(last_token));
    }
    return excerpt(message, 300);
  }

  std::string_view text_;
  const std::filesystem::path& file_;
  const char* const& last_read_;
  std::vector<Open> open_;
  json* pending_ = nullptr;
};

}  // namespace

std::string line_and_column(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  const auto head = text.substr(0, offset);
  const auto line = 1 + std::count(head.begin(), head.end(), '\n');
  const auto nl = head.rfind('\n');
  const std::size_t column = nl == std::string_view::npos ? offset + 1 : offset - nl;
  return fmt::format("{}:{}", line, column);
}

json parse_json(std::string_view text, const std::filesystem::path& file) {
  const char* last_read = text.data();
  CheckedBuilder builder(text, file, last_read);
  const TrackingIterator first{text.data(), &last_read}, last{text.data() + text.size(), &last_read};
  const bool ok = json::sax_parse(first, last, &builder);
  if (!ok || !builder.error.empty()) {
    if (builder.error.empty()) fail("{}: malformed JSON", file.string());
    fail("{}", builder.error);
  }
  return std::move(builder.root);
}

}  // namespace bouguer
