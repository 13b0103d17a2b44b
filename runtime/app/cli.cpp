#include "cli.h"

#include <charconv>
#include <filesystem>
#include <iostream>

#include "annex/formats/text_lexer.h"

namespace annex::cli {

bool ParsedArgs::has(std::string_view name) const {
  for (const auto& [k, v] : options)
    if (k == name) return true;
  return false;
}

std::optional<std::string> ParsedArgs::get(std::string_view name) const {
  for (const auto& [k, v] : options)
    if (k == name) return v;
  return std::nullopt;
}

std::optional<ParsedArgs> parse_args(std::string_view command, const std::vector<std::string>& args,
                                     const ArgSpec& spec) {
  auto listed = [](const std::vector<std::string_view>& names, std::string_view n) {
    for (auto x : names)
      if (x == n) return true;
    return false;
  };
  ParsedArgs out;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.size() < 3 || a.rfind("--", 0) != 0) {
      out.positional.push_back(a);
      continue;
    }
    std::string name = a.substr(2), value;
    const size_t eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name.resize(eq);
    }
    if (listed(spec.with_value, name)) {
      if (!inline_value) {
        if (i + 1 >= args.size()) {
          std::cerr << "annex-runtime " << command << ": error: --" << name << " needs a value\n";
          return std::nullopt;
        }
        value = args[++i];
      }
    } else if (!listed(spec.flags, name) || inline_value) {
      std::vector<std::string> known;
      for (auto n : spec.flags) known.push_back("--" + std::string(n));
      for (auto n : spec.with_value) known.push_back("--" + std::string(n));
      known.push_back("--help");
      std::cerr << "annex-runtime " << command << ": error: unknown option '" << a << "'"
                << did_you_mean("--" + name, known) << " (see annex-runtime " << command
                << " --help)\n";
      return std::nullopt;
    }
    out.options.emplace_back(std::move(name), std::move(value));
  }
  return out;
}

int fail(std::string_view command, std::string_view message, int code) {
  std::cerr << "annex-runtime " << command << ": error: " << message << "\n";
  return code;
}

bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

std::optional<long> parse_count(std::string_view command, std::string_view option,
                                const std::string& text) {
  long n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || end != text.data() + text.size() || n < 0) {
    std::cerr << "annex-runtime " << command << ": error: --" << option
              << " expects a whole number >= 0, got '" << text << "'\n";
    return std::nullopt;
  }
  return n;
}

void create_parent_dirs(const std::string& file) {
  const std::filesystem::path dir = std::filesystem::path(file).parent_path();
  std::error_code ec;
  if (!dir.empty()) std::filesystem::create_directories(dir, ec);
}

std::string plural(long long n, std::string_view noun) {
  return std::to_string(n) + " " + std::string(noun) + (n == 1 ? "" : "s");
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  std::vector<std::string_view> views(candidates.begin(), candidates.end());
  const std::string s = detail::suggestion(word, views);
  return s.starts_with("; did you mean") ? s : "";
}

}  // namespace annex::cli
