#include "annex/formats/text_lexer.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>

namespace annex::detail {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t';
}

bool is_control(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u < 0x20 || u == 0x7f;
}

std::string hex_byte(char c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02X", static_cast<unsigned>(static_cast<unsigned char>(c)));
  return buf;
}

}  // namespace

Error error_at(std::string_view origin, int line, int column, std::string message) {
  return Error{std::move(message), Location{std::string(origin), line, column}};
}

Error error_at(std::string_view origin, const Token& token, std::string message) {
  return error_at(origin, token.line, token.column, std::move(message));
}

std::string shown(const Token& token) {
  std::string out(1, '\'');
  if (token.quoted) {
    out += '"';
    for (char c : token.text) {
      if (c == '"' || c == '\\') out += '\\';
      out += c;
    }
    out += '"';
  } else {
    out += token.text;
  }
  out += '\'';
  return out;
}

Lexer::Lexer(std::string_view text, std::string_view origin) : text_(text), origin_(origin) {
  if (text_.starts_with("\xEF\xBB\xBF")) pos_ = 3;
}

Status Lexer::check_size(std::size_t max_bytes) const {
  if (text_.size() > max_bytes)
    return error_at(origin_, 1, 1,
                    "input is " + std::to_string(text_.size()) + " bytes, more than the limit of " +
                        std::to_string(max_bytes) + " bytes");
  return Ok{};
}

Location Lexer::end_location() const {
  const auto lines = std::count(text_.begin(), text_.end(), '\n');
  const std::size_t last_nl = text_.rfind('\n');
  const std::size_t last_len =
      last_nl == std::string_view::npos ? text_.size() : text_.size() - last_nl - 1;
  return Location{origin_, static_cast<int>(lines) + 1, static_cast<int>(last_len) + 1};
}

Result<bool> Lexer::next(Line& out) {
  while (pos_ < text_.size()) {
    std::size_t eol = text_.find('\n', pos_);
    if (eol == std::string_view::npos) eol = text_.size();
    std::string_view s = text_.substr(pos_, eol - pos_);
    const std::size_t line_start = pos_;
    pos_ = eol < text_.size() ? eol + 1 : eol;
    ++line_;
    if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
    // The BOM, if any, was skipped; columns still count from the line's first byte.
    const int col0 = line_ == 1 ? static_cast<int>(line_start) : 0;
    if (s.size() > kMaxLineBytes)
      return error_at(origin_, line_, static_cast<int>(kMaxLineBytes) + 1 + col0,
                      "line is longer than " + std::to_string(kMaxLineBytes) + " bytes");

    out.number = line_;
    out.tokens.clear();
    out.end_column = 0;
    std::size_t i = 0;
    while (i < s.size()) {
      const char c = s[i];
      if (is_space(c)) {
        ++i;
        continue;
      }
      if (c == '#') break;
      Token tok;
      tok.line = line_;
      tok.column = static_cast<int>(i) + 1 + col0;
      if (c == '"') {
        tok.quoted = true;
        std::size_t j = i + 1;
        bool closed = false;
        while (j < s.size()) {
          const char d = s[j];
          if (d == '"') {
            closed = true;
            ++j;
            break;
          }
          if (d == '\\') {
            if (j + 1 < s.size() && (s[j + 1] == '"' || s[j + 1] == '\\')) {
              tok.text += s[j + 1];
              j += 2;
              continue;
            }
            return error_at(origin_, line_, static_cast<int>(j) + 1 + col0,
                            "unknown escape in string; only \\\" and \\\\ are allowed");
          }
          if (is_control(d))
            return error_at(origin_, line_, static_cast<int>(j) + 1 + col0,
                            "control character " + hex_byte(d) + " in string");
          tok.text += d;
          ++j;
        }
        if (!closed) return error_at(origin_, tok, "unterminated string; expected a closing '\"'");
        if (j < s.size() && !is_space(s[j]) && s[j] != '#')
          return error_at(origin_, line_, static_cast<int>(j) + 1 + col0,
                          "expected a space after the closing '\"'");
        i = j;
      } else {
        const std::size_t start = i;
        while (i < s.size() && !is_space(s[i]) && s[i] != '#') {
          if (s[i] == '"')
            return error_at(origin_, line_, static_cast<int>(i) + 1 + col0,
                            "unexpected '\"' inside a token; quote the whole token");
          if (is_control(s[i]))
            return error_at(origin_, line_, static_cast<int>(i) + 1 + col0,
                            "control character " + hex_byte(s[i]) + " is not allowed");
          ++i;
        }
        tok.text.assign(s.substr(start, i - start));
      }
      out.end_column = static_cast<int>(i) + 1 + col0;
      out.tokens.push_back(std::move(tok));
    }
    if (!out.tokens.empty()) return true;
  }
  return false;
}

bool is_identifier(std::string_view s) {
  if (s.empty()) return false;
  const auto alpha = [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
  };
  if (!alpha(s[0])) return false;
  return std::all_of(s.begin() + 1, s.end(), [&](char c) {
    return alpha(c) || (c >= '0' && c <= '9') || c == '.' || c == '-';
  });
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  // Two rows over the shorter word; on the stack when it is short, as every key is
  // (suggestion() runs for each unknown key of a file, so it must not allocate).
  if (b.size() > a.size()) std::swap(a, b);
  constexpr std::size_t kStackRow = 64;
  std::array<std::size_t, kStackRow + 1> stack_prev{}, stack_cur{};
  std::vector<std::size_t> heap_prev, heap_cur;
  std::span<std::size_t> prev(stack_prev), cur(stack_cur);
  if (b.size() > kStackRow) {
    heap_prev.resize(b.size() + 1);
    heap_cur.resize(b.size() + 1);
    prev = heap_prev;
    cur = heap_cur;
  }
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string suggestion(std::string_view word, std::span<const std::string_view> candidates) {
  // Close enough to be a typo: one edit for short words, up to three for long ones.
  const std::size_t limit = std::min<std::size_t>(3, word.size() / 3 + 1);
  std::string_view best;
  std::size_t best_d = limit + 1;
  if (word.size() <= 64) {
    for (std::string_view c : candidates) {
      // The distance is at least the difference in length: no need to compute it.
      const std::size_t length_gap =
          word.size() > c.size() ? word.size() - c.size() : c.size() - word.size();
      if (length_gap >= best_d) continue;
      const std::size_t d = edit_distance(word, c);
      if (d < best_d) {
        best_d = d;
        best = c;
      }
    }
  }
  if (!best.empty()) return "; did you mean '" + std::string(best) + "'?";
  std::string out = "; expected one of: ";
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (i > 0) out += ", ";
    out += candidates[i];
  }
  return out;
}

Error LineReader::missing(std::string message) const {
  return error_at(origin_, line_.number, line_.end_column, std::move(message));
}

Result<double> LineReader::number(std::string_view after) {
  if (at_end()) return missing("expected a number after '" + std::string(after) + "'");
  const Token& t = take();
  double v = 0;
  const char* first = t.text.data();
  const char* last = first + t.text.size();
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (t.quoted || ptr != last || (ec != std::errc{} && ec != std::errc::result_out_of_range))
    return error_at(origin_, t,
                    "expected a number after '" + std::string(after) + "', found " + shown(t));
  if (ec == std::errc::result_out_of_range)
    return error_at(origin_, t,
                    "number " + shown(t) + " after '" + std::string(after) + "' is out of range");
  if (!std::isfinite(v))
    return error_at(
        origin_, t,
        "expected a finite number after '" + std::string(after) + "', found " + shown(t));
  return v + 0.0;  // -0 becomes 0, so the writer's "0" reads back identically
}

Result<double> LineReader::unit_interval(std::string_view after) {
  auto v = number(after);
  if (!v) return v;
  if (auto msg = check_unit_interval(*v, after)) return error_at(origin_, last(), *msg);
  return v;
}

Result<double> LineReader::positive(std::string_view after) {
  auto v = number(after);
  if (!v) return v;
  if (auto msg = check_positive(*v, after)) return error_at(origin_, last(), *msg);
  return v;
}

Result<int> LineReader::non_negative_int(std::string_view after) {
  if (at_end()) return missing("expected a whole number after '" + std::string(after) + "'");
  const Token& t = take();
  int v = 0;
  const char* first = t.text.data();
  const char* last = first + t.text.size();
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (t.quoted || ptr != last || (ec != std::errc{} && ec != std::errc::result_out_of_range))
    return error_at(
        origin_, t,
        "expected a whole number after '" + std::string(after) + "', found " + shown(t));
  if (ec == std::errc::result_out_of_range)
    return error_at(origin_, t,
                    "number " + shown(t) + " after '" + std::string(after) + "' is out of range");
  if (v < 0)
    return error_at(origin_, t, std::string(after) + " must be 0 or more, found " + t.text);
  return v;
}

Result<std::string> LineReader::identifier(std::string_view what, std::string_view after) {
  if (at_end())
    return missing("expected " + std::string(what) + " after '" + std::string(after) + "'");
  const Token& t = take();
  if (t.quoted || !is_identifier(t.text))
    return error_at(origin_, t, invalid_name_message(what, shown(t)));
  return t.text;
}

Status LineReader::expect_end(std::string_view after) {
  if (at_end()) return Ok{};
  const Token& t = peek();
  return error_at(origin_, t,
                  "unexpected " + shown(t) + " after '" + std::string(after) +
                      "'; expected the end of the line");
}

std::string format_number(double v) {
  if (v == 0) return "0";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

bool has_control_char(std::string_view s) {
  return std::any_of(s.begin(), s.end(), is_control);
}

std::string quote_if_needed(std::string_view s) {
  const bool needs = s.empty() || std::any_of(s.begin(), s.end(), [](char c) {
                       return is_space(c) || c == '#' || c == '"';
                     });
  if (!needs) return std::string(s);
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  out += '"';
  return out;
}

std::string invalid_name_message(std::string_view what, std::string_view shown_name) {
  return "invalid " + std::string(what) + " " + std::string(shown_name) +
         "; a name starts with a letter or '_' and continues with letters, digits, '_', '.' "
         "or '-'";
}

std::optional<std::string> check_unit_interval(double v, std::string_view key) {
  if (std::isfinite(v) && v >= 0 && v <= 1) return std::nullopt;
  return std::string(key) + " must be in [0, 1], found " + format_number(v);
}

std::optional<std::string> check_positive(double v, std::string_view key) {
  if (std::isfinite(v) && v > 0) return std::nullopt;
  return std::string(key) + " must be positive, found " + format_number(v);
}

std::optional<std::string> check_finite(double v, std::string_view key) {
  if (std::isfinite(v)) return std::nullopt;
  return std::string(key) + " must be a finite number, found " + format_number(v);
}

std::optional<std::string> check_scale_min(double min) {
  if (std::isfinite(min) && min > 0) return std::nullopt;
  return "scale minimum must be positive, found " + format_number(min);
}

std::optional<std::string> check_scale_order(double min, double max) {
  if (std::isfinite(max) && min <= max) return std::nullopt;
  return "scale minimum " + format_number(min) + " is larger than maximum " + format_number(max);
}

std::optional<std::string> check_torus(double major, double minor) {
  if (minor < major) return std::nullopt;
  return "torus minor_radius " + format_number(minor) + " must be smaller than major_radius " +
         format_number(major);
}

Status read_header(LineReader& r, const Token& key, std::string_view name, int version) {
  const std::string_view origin = r.origin();
  const std::string expected = std::string(name) + " " + std::to_string(version);
  if (key.quoted || key.text != name) {
    std::string hint;
    if (key.text != name) {
      if (key.text == "annex-haptic") hint = " (this is a .haptic file)";
      if (key.text == "annex-scene") hint = " (this is a .scene file)";
      if (key.text == "annex-hmd") hint = " (this is an HMD config file)";
    }
    return error_at(origin, key,
                    "expected the header '" + expected + "', found " + shown(key) + hint);
  }
  auto found = r.non_negative_int(name);
  if (!found) return found.error();
  if (*found != version)
    return error_at(origin, r.last(),
                    "unsupported format version " + std::to_string(*found) +
                        "; this reader knows version " + std::to_string(version));
  return r.expect_end(expected);
}

}  // namespace annex::detail
