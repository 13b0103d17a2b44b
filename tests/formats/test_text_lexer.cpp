#include "annex/formats/text_lexer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace annex::detail {
namespace {

std::vector<Line> lex_all(std::string_view text) {
  Lexer lexer(text, "t");
  std::vector<Line> lines;
  Line line;
  for (;;) {
    auto more = lexer.next(line);
    EXPECT_TRUE(more.ok()) << more.error().format();
    if (!more.ok() || !*more) break;
    lines.push_back(line);
  }
  return lines;
}

TEST(TextLexer, SplitsTokensWithColumnsAndSkipsComments) {
  const auto lines = lex_all("  a  bb\t\"c d\" # x\n\n# only\n\tz#w\n");
  ASSERT_EQ(lines.size(), 2u);
  ASSERT_EQ(lines[0].tokens.size(), 3u);
  EXPECT_EQ(lines[0].number, 1);
  EXPECT_EQ(lines[0].tokens[0].text, "a");
  EXPECT_EQ(lines[0].tokens[0].column, 3);
  EXPECT_EQ(lines[0].tokens[1].column, 6);
  EXPECT_EQ(lines[0].tokens[2].text, "c d");
  EXPECT_TRUE(lines[0].tokens[2].quoted);
  EXPECT_EQ(lines[0].tokens[2].column, 9);
  EXPECT_EQ(lines[0].end_column, 14);
  EXPECT_EQ(lines[1].number, 4);
  EXPECT_EQ(lines[1].tokens[0].text, "z");
}

TEST(TextLexer, QuotedEscapes) {
  const auto lines = lex_all("\"a\\\"b\\\\c\" \"\"\n");
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].tokens[0].text, "a\"b\\c");
  EXPECT_EQ(lines[0].tokens[1].text, "");
}

TEST(TextLexer, EndLocation) {
  EXPECT_EQ(Lexer("", "t").end_location(), (Location{"t", 1, 1}));
  EXPECT_EQ(Lexer("ab\ncd", "t").end_location(), (Location{"t", 2, 3}));
  EXPECT_EQ(Lexer("ab\ncd\n", "t").end_location(), (Location{"t", 3, 1}));
}

TEST(TextLexer, Identifiers) {
  EXPECT_TRUE(is_identifier("a"));
  EXPECT_TRUE(is_identifier("_x.y-z9"));
  EXPECT_FALSE(is_identifier(""));
  EXPECT_FALSE(is_identifier("9a"));
  EXPECT_FALSE(is_identifier(".a"));
  EXPECT_FALSE(is_identifier("a b"));
  EXPECT_FALSE(is_identifier("caf\xC3\xA9"));
}

TEST(TextLexer, SuggestionsAndEditDistance) {
  EXPECT_EQ(edit_distance("raduis", "radius"), 2u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("sitting", "kitten"), 3u);
  // Words longer than the stack row (64) in either position.
  const std::string long_a(100, 'a');
  const std::string long_b = std::string(70, 'a') + "b";
  EXPECT_EQ(edit_distance(long_a, long_b), 30u);
  EXPECT_EQ(edit_distance(long_b, long_a), 30u);
  EXPECT_EQ(edit_distance(long_a, "b"), 100u);
  const std::string_view keys[] = {"radius", "height", "end"};
  EXPECT_EQ(suggestion("raduis", keys), "; did you mean 'radius'?");
  EXPECT_EQ(suggestion("ed", keys), "; did you mean 'end'?");
  EXPECT_EQ(suggestion("x", keys), "; expected one of: radius, height, end");
}

TEST(TextLexer, NumbersWriteShortestAndReadBackExactly) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(-0.0), "0");
  EXPECT_EQ(format_number(1.0), "1");
  EXPECT_EQ(format_number(1e-5), "1e-05");
  EXPECT_EQ(format_number(123456789.0), "123456789");
  std::mt19937_64 rng(7);
  for (int i = 0; i < 10000; ++i) {
    const std::uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v)) continue;
    Line line;
    line.number = 1;
    line.tokens.push_back(Token{format_number(v), 1, 1, false});
    LineReader r(line, "t");
    auto back = r.number("x");
    if (!back.ok()) {
      // Subnormals may be reported out of range by from_chars; never anything else.
      ASSERT_LT(std::abs(v), std::numeric_limits<double>::min()) << format_number(v);
      continue;
    }
    ASSERT_EQ(*back, v == 0 ? 0.0 : v) << format_number(v);
  }
}

TEST(TextLexer, QuoteIfNeeded) {
  EXPECT_EQ(quote_if_needed("a/b.obj"), "a/b.obj");
  EXPECT_EQ(quote_if_needed("a\\b"), "a\\b");
  EXPECT_EQ(quote_if_needed("a b"), "\"a b\"");
  EXPECT_EQ(quote_if_needed("a#b"), "\"a#b\"");
  EXPECT_EQ(quote_if_needed("a\"b\\"), "\"a\\\"b\\\\\"");
  EXPECT_EQ(quote_if_needed(""), "\"\"");
}

}  // namespace
}  // namespace annex::detail
