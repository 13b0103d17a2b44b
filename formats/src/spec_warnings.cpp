#include "annex/formats/spec_warnings.h"

#include <algorithm>
#include <string>
#include <utility>

namespace annex {
namespace {

// The `mesh` lines of each object block, found by the same words the reader uses.
struct MeshLine {
  std::string object;
  std::string path;
  Location where;
};

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

std::vector<MeshLine> mesh_lines(std::string_view text, std::string_view origin,
                                 Location* first_object) {
  std::vector<MeshLine> out;
  std::string object;
  int line_no = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line = text.substr(start, end - start);
    ++line_no;
    std::vector<std::pair<std::string_view, int>> words;  // word, 1-based column
    for (std::size_t i = 0; i < line.size();) {
      if (line[i] == '#') break;
      if (blank(line[i])) {
        ++i;
        continue;
      }
      std::size_t j = i;
      if (line[i] == '"') {
        const std::size_t close = line.find('"', i + 1);
        const std::size_t stop = close == std::string_view::npos ? line.size() : close;
        words.emplace_back(line.substr(i + 1, stop - i - 1), static_cast<int>(i) + 1);
        j = close == std::string_view::npos ? line.size() : close + 1;
      } else {
        while (j < line.size() && !blank(line[j]) && line[j] != '#') ++j;
        words.emplace_back(line.substr(i, j - i), static_cast<int>(i) + 1);
      }
      i = j;
    }
    if (words.size() >= 2 && words[0].first == "object") {
      object = std::string(words[1].first);
      if (first_object->line == 0)
        *first_object = {std::string(origin), line_no, words[0].second};
    } else if (words.size() >= 2 && words[0].first == "mesh" && !object.empty()) {
      out.push_back({object, std::string(words[1].first),
                     {std::string(origin), line_no, words[1].second}});
    }
    if (end == text.size()) break;
    start = end + 1;
  }
  return out;
}

}  // namespace

std::vector<Diagnostic> spec_warnings(const HapticSpec& spec, std::string_view text,
                                      std::string_view origin,
                                      const std::filesystem::path& spec_dir) {
  std::vector<Diagnostic> out;
  Location first_object;
  const std::vector<MeshLine> meshes = mesh_lines(text, origin, &first_object);
  if (spec.objects.empty()) {
    out.push_back({"the spec has no virtual objects, so 'run' has nothing to annex; add an "
                   "'object NAME ... end' block (docs/haptic-format.md)",
                   {std::string(origin), 1, 1}});
    return out;
  }
  bool any_annexable = false;
  for (const VirtualObject& o : spec.objects) any_annexable |= o.annexable;
  if (!any_annexable)
    out.push_back({"no object is annexable, so 'run' matches no prop and draws nothing on one; "
                   "set 'annexable yes' and give the object a primitive",
                   first_object.line ? first_object : Location{std::string(origin), 1, 1}});
  for (const VirtualObject& o : spec.objects) {
    if (o.mesh.empty()) continue;
    const std::filesystem::path p = spec_dir / o.mesh;
    std::error_code ec;
    if (std::filesystem::is_regular_file(p, ec)) continue;
    Location where{std::string(origin), 0, 0};
    for (const MeshLine& m : meshes)
      if (m.object == o.name) where = m.where;
    out.push_back({"object '" + o.name + "': mesh '" + o.mesh + "' does not exist (" +
                       p.lexically_normal().string() +
                       "); paths are relative to the spec's folder, and the runtime draws "
                       "the object's primitives instead",
                   where});
  }
  return out;
}

}  // namespace annex
