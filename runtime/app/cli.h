#pragma once
// The small command-line layer of annex-runtime: each subcommand is a function
// taking its arguments and returning the process exit code.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace annex::cli {

// Exit codes scripts rely on (docs/cli.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // the job ran and failed (no plane, sensor lost...)
inline constexpr int kExitBadInput = 2; // bad arguments, unreadable or invalid input files

struct Command {
  std::string_view name;
  std::string_view summary;
  std::string_view usage;  // full --help text
  int (*run)(const std::vector<std::string>& args);
};

// Splits arguments into positionals and --options. Options listed in `with_value`
// take the next argument (or --opt=value); others are flags. Unknown options are errors.
struct ParsedArgs {
  std::vector<std::string> positional;
  std::vector<std::pair<std::string, std::string>> options;  // name without "--", value
  bool has(std::string_view name) const;
  std::optional<std::string> get(std::string_view name) const;
};

struct ArgSpec {
  std::vector<std::string_view> flags;
  std::vector<std::string_view> with_value;
};

// Prints "annex-runtime <cmd>: error: ..." and returns nullopt on a bad argument list.
std::optional<ParsedArgs> parse_args(std::string_view command, const std::vector<std::string>& args,
                                     const ArgSpec& spec);

bool wants_help(const std::vector<std::string>& args);

// Prints "annex-runtime <command>: error: <message>" and returns `code`.
int fail(std::string_view command, std::string_view message, int code);

// Parses a whole non-negative integer option; prints an error and returns nullopt otherwise.
std::optional<long> parse_count(std::string_view command, std::string_view option,
                                const std::string& text);

// Creates the folder an output file goes into, as `run --out DIR` creates DIR (errors
// show when the file is written).
void create_parent_dirs(const std::string& file);

// "1 virtual object", "3 virtual objects": counts in messages read as English.
std::string plural(long long n, std::string_view noun);

// "; did you mean '--frames'?" for a mistyped name close to one of `candidates`,
// else "" (the spec reader's Levenshtein rule, text_lexer.h).
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace annex::cli
