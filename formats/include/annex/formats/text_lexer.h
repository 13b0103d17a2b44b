#pragma once
// The line-oriented lexer shared by the .haptic and .scene readers, plus the small
// helpers both readers and writers need (strict numbers, identifiers, did-you-mean,
// shortest round-trip number text). Also used by the other `key value` config
// files (HMD, scan) so every Annex text file reports errors the same way.

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/result.h"

namespace annex::detail {

// Hostile-input caps shared by both formats (documented in docs/haptic-format.md).
inline constexpr std::size_t kMaxLineBytes = 4096;
inline constexpr std::size_t kMaxObjects = 4096;
inline constexpr std::size_t kMaxPrimitivesPerObject = 64;

struct Token {
  std::string text;  // unescaped for quoted tokens
  int line = 0;
  int column = 0;  // 1-based byte column of the token's first character
  bool quoted = false;
};

// One line that holds at least one token (blank and comment-only lines are skipped).
struct Line {
  int number = 0;
  int end_column = 0;  // column just after the last token, for "expected X after Y"
  std::vector<Token> tokens;
};

// Splits text into lines of tokens, one line at a time, so memory stays bounded by
// the longest line. Whitespace is space or tab; '#' outside quotes starts a comment;
// "..." quotes a token with \" and \\ escapes; CRLF is accepted; a leading UTF-8 BOM
// is skipped; any other control character is an error.
class Lexer {
 public:
  Lexer(std::string_view text, std::string_view origin);

  // Checks the whole-input size limit; call once before next().
  Status check_size(std::size_t max_bytes) const;

  // Reads the next non-empty line into `out`; returns false at end of input.
  Result<bool> next(Line& out);

  // Where "end of input" errors point: the line after the last newline, column 1,
  // or just past the last character when the text does not end with a newline.
  Location end_location() const;

  const std::string& origin() const { return origin_; }

 private:
  std::string_view text_;
  std::string origin_;
  std::size_t pos_ = 0;
  int line_ = 0;
};

Error error_at(std::string_view origin, int line, int column, std::string message);
Error error_at(std::string_view origin, const Token& token, std::string message);

// A token as it is quoted in a message: 'abc' or '"a b"'.
std::string shown(const Token& token);

// [A-Za-z_][A-Za-z0-9_.-]*
bool is_identifier(std::string_view s);

// "; did you mean 'radius'?" when a candidate is close (Levenshtein), otherwise
// "; expected one of: a, b, c".
std::string suggestion(std::string_view word, std::span<const std::string_view> candidates);
std::size_t edit_distance(std::string_view a, std::string_view b);

// Reads the tokens of one line left to right with the error messages both formats use.
class LineReader {
 public:
  LineReader(const Line& line, std::string_view origin) : line_(line), origin_(origin) {}

  bool at_end() const { return i_ >= line_.tokens.size(); }
  const Token& peek() const { return line_.tokens[i_]; }
  const Token& take() { return line_.tokens[i_++]; }

  // Location just after the last token, where a missing value is reported.
  Error missing(std::string message) const;

  // A finite number (whole token, std::from_chars); `after` names the key it belongs to.
  Result<double> number(std::string_view after);
  // A number in [0, 1].
  Result<double> unit_interval(std::string_view after);
  // A number > 0.
  Result<double> positive(std::string_view after);
  Result<int> non_negative_int(std::string_view after);
  // An unquoted identifier; `what` is e.g. "object name".
  Result<std::string> identifier(std::string_view what, std::string_view after);
  // No tokens left; `after` describes what came before, for the message.
  Status expect_end(std::string_view after);

  // Token location of the most recently taken token.
  const Token& last() const { return line_.tokens[i_ - 1]; }
  std::string_view origin() const { return origin_; }

 private:
  const Line& line_;
  std::string_view origin_;
  std::size_t i_ = 0;
};

// The versioned header every Annex text file starts with, e.g. "annex-haptic 1".
// `key` is the line's first token, already taken from `r`; the rest of the line must
// be the version. Another Annex header gets a hint ("this is a .scene file").
Status read_header(LineReader& r, const Token& key, std::string_view name, int version);

// Shortest text that reads back as the same double (std::to_chars); -0 is written as 0.
std::string format_number(double v);

// A string as a single token: bare when it can be, otherwise quoted with escapes.
std::string quote_if_needed(std::string_view s);

// Bytes that can never appear in a token or a quoted string.
bool has_control_char(std::string_view s);

// The rules both the readers and validate_haptic apply, so an in-memory spec and a
// file get the same words. Each returns the message when the rule is broken.
std::string invalid_name_message(std::string_view what, std::string_view shown_name);
std::optional<std::string> check_unit_interval(double v, std::string_view key);
std::optional<std::string> check_positive(double v, std::string_view key);
std::optional<std::string> check_finite(double v, std::string_view key);
std::optional<std::string> check_scale_min(double min);
std::optional<std::string> check_scale_order(double min, double max);
std::optional<std::string> check_torus(double major, double minor);

// Unit-length tolerances: rotations and axes within kNormTolerance of 1 are
// normalised on read, beyond it rejected; within kNormExact they are kept bit for
// bit so that written values read back identically.
inline constexpr double kNormTolerance = 1e-3;
inline constexpr double kNormExact = 1e-9;

}  // namespace annex::detail
