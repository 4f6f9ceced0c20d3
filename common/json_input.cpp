#include "common/json_input.hpp"

#include <variant>
#include <vector>

#include <fmt/format.h>

#include "common/args.hpp"
#include "common/io.hpp"

namespace sglab::io {

using ordered_json = nlohmann::ordered_json;

// ---------------------------------------------------------------------------
// Parsing: a SAX handler that builds the document, tracks the key path for
// messages, limits the depth and refuses duplicate keys and numbers that do
// not survive as doubles.
// ---------------------------------------------------------------------------
namespace {

class StrictBuilder : public nlohmann::json_sax<ordered_json> {
 public:
  ordered_json root;
  std::string error;  // empty on success

  bool null() override { return put(nullptr); }
  bool boolean(bool v) override { return put(v); }
  bool number_integer(number_integer_t v) override { return put(v); }
  bool number_unsigned(number_unsigned_t v) override { return put(v); }
  bool number_float(number_float_t v, const string_t& text) override {
    const auto checked = io::parse_decimal(text);
    if (const auto* why = std::get_if<std::string>(&checked)) return stop(*why);
    return put(v);
  }
  bool string(string_t& v) override { return put(std::move(v)); }
  bool binary(binary_t&) override { return stop("binary values are not JSON text"); }
  bool start_object(std::size_t) override { return open(ordered_json::object()); }
  bool start_array(std::size_t) override { return open(ordered_json::array()); }
  bool key(string_t& k) override {
    if (stack_.back()->contains(k)) {
      keys_.back() = k;
      return stop("duplicate key");
    }
    keys_.back() = std::move(k);
    return true;
  }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string& last_token,
                   const nlohmann::detail::exception& e) override {
    if (e.id == 406) {  // out_of_range.406: a number beyond the largest double, said as
                        // parse_decimal says it
      const auto checked = io::parse_decimal(last_token);
      if (const auto* why = std::get_if<std::string>(&checked)) return stop(*why);
    }
    std::string what = e.what();
    if (const auto pos = what.find("] "); pos != std::string::npos)
      what = what.substr(pos + 2);  // drop "[json.exception...]"
    // The library quotes the whole last token (a 50 MB string, control bytes
    // as <U+0001>): quote it escaped and shortened instead.
    const std::string quoted = "last read: '" + last_token + "'";
    if (const auto pos = what.find(quoted); pos != std::string::npos)
      what.replace(pos, quoted.size(), "last read: " + io::quote_escaped(last_token));
    return stop(what.substr(0, 4 * io::kMaxQuotedChars + 200));
  }

  // The key path of the current position, e.g. provenance.achieved.objective or
  // coefficients.small[3].
  std::string path() const {
    std::string p;
    for (std::size_t i = 0; i < stack_.size(); ++i) {
      const ordered_json& c = *stack_[i];
      const bool innermost = i + 1 == stack_.size();
      if (c.is_array())
        p += fmt::format("[{}]", innermost ? c.size() : c.size() - 1);
      else if (!keys_[i].empty() || !innermost)
        p += (p.empty() ? "" : ".") + keys_[i];
    }
    return p;
  }

 private:
  bool stop(const std::string& why) {
    if (error.empty()) {
      const std::string where = path();
      error = where.empty() ? why : fmt::format("key {}: {}", io::quote_escaped(where), why);
    }
    return false;
  }
  ordered_json* slot() {
    if (stack_.empty()) return &root;
    ordered_json& top = *stack_.back();
    if (top.is_array()) {
      top.push_back(nullptr);
      return &top.back();
    }
    return &top[keys_.back()];
  }
  bool put(ordered_json v) {
    *slot() = std::move(v);
    return true;
  }
  bool open(ordered_json container) {
    if (stack_.size() >= static_cast<std::size_t>(kMaxJsonDepth))
      return stop(fmt::format("nested deeper than {} levels", kMaxJsonDepth));
    ordered_json* s = slot();
    *s = std::move(container);
    stack_.push_back(s);
    keys_.emplace_back();
    return true;
  }
  bool close() {
    stack_.pop_back();
    keys_.pop_back();
    return true;
  }

  // open containers (pointers stay valid: only the innermost grows)
  std::vector<ordered_json*> stack_;
  std::vector<std::string> keys_;  // the current key of each open object
};

}  // namespace

nlohmann::ordered_json parse_json_strict(std::string_view text, std::string_view source) {
  StrictBuilder builder;
  const bool ok =
      ordered_json::sax_parse(text, &builder, ordered_json::input_format_t::json, /*strict=*/true);
  if (!ok || !builder.error.empty())
    throw InputError(fmt::format("{}: malformed JSON: {}", source,
                                 builder.error.empty() ? "parse failed" : builder.error));
  return std::move(builder.root);
}

nlohmann::ordered_json read_json_file(const std::filesystem::path& path, std::size_t max_bytes,
                                      std::string_view what) {
  return parse_json_strict(read_input_file(path, max_bytes, what), path.string());
}

}  // namespace sglab::io
