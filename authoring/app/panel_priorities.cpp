// Priorities (paper Figure 2c): w_o per object, w_s per primitive, w_h per dimension,
// as 0-1 sliders or, in forced-rank mode, lists dragged into order whose weights
// follow rank_weights().
#include <functional>
#include <string>
#include <vector>

#include "annex/authoring/rank.h"
#include "panels.h"

namespace annex::authoring {

namespace {

// A list in rank order; dragging an item onto another (or the arrows) reorders it.
void rank_list(const char* id, const std::vector<std::string>& names,
               const std::vector<double>& weights,
               const std::function<void(std::vector<int>)>& emit) {
  const std::vector<int> order = order_by_weight(weights);
  ImGui::PushID(id);
  for (int r = 0; r < static_cast<int>(order.size()); ++r) {
    ImGui::PushID(r);
    const int item = order[r];
    if (ImGui::ArrowButton("up", ImGuiDir_Up) && r > 0) {
      std::vector<int> next = order;
      std::swap(next[r], next[r - 1]);
      emit(next);
    }
    ImGui::SameLine();
    if (ImGui::ArrowButton("down", ImGuiDir_Down) && r + 1 < static_cast<int>(order.size())) {
      std::vector<int> next = order;
      std::swap(next[r], next[r + 1]);
      emit(next);
    }
    ImGui::SameLine();
    // append(), not operator+: GCC 12 warns falsely (-Wrestrict) on chained string +.
    std::string label = "#";
    label.append(std::to_string(r + 1)).append("  ").append(names[item]);
    ImGui::Selectable(label.c_str(), false);
    if (ImGui::BeginDragDropSource()) {
      ImGui::SetDragDropPayload("ANNEX_RANK", &r, sizeof r);
      ImGui::Text("%s", names[item].c_str());
      ImGui::EndDragDropSource();
    }
    if (ImGui::BeginDragDropTarget()) {
      if (const ImGuiPayload* payload = ImGui::AcceptDragDropPayload("ANNEX_RANK")) {
        const int from = *static_cast<const int*>(payload->Data);
        std::vector<int> next = order;
        const int moved = next[from];
        next.erase(next.begin() + from);
        next.insert(next.begin() + r, moved);
        emit(next);
      }
      ImGui::EndDragDropTarget();
    }
    ImGui::SameLine(ImGui::GetContentRegionAvail().x - 30);
    ImGui::TextDisabled("%.2f", weights[item]);
    ImGui::PopID();
  }
  ImGui::PopID();
}

void weight_slider(const std::string& label, double value, CommandQueue& queue, cmd::SetWeight c) {
  float v = static_cast<float>(value);
  if (ImGui::SliderFloat(label.c_str(), &v, 0.f, 1.f, "%.2f")) {
    c.weight = v;
    queue.push(c);
  }
  if (ImGui::IsItemDeactivatedAfterEdit()) queue.push(cmd::EndEdit{});
}

}  // namespace

void draw_priorities(const EditorDocument& doc, UiState& ui, CommandQueue& queue) {
  place_next_window(ui.layout.priorities);
  if (!ImGui::Begin(
          "Priorities", nullptr,
          ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
              ImGuiWindowFlags_HorizontalScrollbar)) {
    ImGui::End();
    return;
  }
  int mode = ui.rank_mode ? 1 : 0;
  ImGui::RadioButton("weights", &mode, 0);
  ImGui::SameLine();
  ImGui::RadioButton("forced rank", &mode, 1);
  ui.rank_mode = mode == 1;
  if (ui.rank_mode && ImGui::IsItemHovered())
    ImGui::SetTooltip("Drag items into order; rank r of n gets weight (n - r) / n.");

  const auto& objects = doc.spec().objects;
  const Selection sel = doc.selection();
  auto emit = [&](WeightLevel level, int o, int p) {
    return [&queue, level, o, p](std::vector<int> order) {
      queue.push(cmd::SetRank{level, o, p, std::move(order)});
      queue.push(cmd::EndEdit{});
    };
  };
  ImGui::PushItemWidth(-100);

  section("Objects (w_o)");
  std::vector<std::string> names;
  std::vector<double> weights;
  for (const VirtualObject& o : objects) {
    names.push_back(o.name);
    weights.push_back(o.priority);
  }
  if (ui.rank_mode) {
    rank_list("objects", names, weights, emit(WeightLevel::object, -1, -1));
  } else {
    for (int o = 0; o < static_cast<int>(objects.size()); ++o) {
      ImGui::PushID(o);
      weight_slider(objects[o].name, objects[o].priority, queue,
                    {WeightLevel::object, o, -1, -1, 0});
      ImGui::PopID();
    }
  }

  if (sel.object >= 0) {
    const VirtualObject& obj = objects[sel.object];
    std::string title = "Primitives of ";
    title.append(obj.name).append(" (w_s)");
    section(title.c_str());
    names.clear();
    weights.clear();
    for (const Primitive& p : obj.primitives) {
      names.push_back(p.name);
      weights.push_back(p.weight);
    }
    if (ui.rank_mode) {
      rank_list("primitives", names, weights, emit(WeightLevel::primitive, sel.object, -1));
    } else {
      for (int p = 0; p < static_cast<int>(obj.primitives.size()); ++p) {
        ImGui::PushID(1000 + p);
        weight_slider(obj.primitives[p].name, obj.primitives[p].weight, queue,
                      {WeightLevel::primitive, sel.object, p, -1, 0});
        ImGui::PopID();
      }
    }
    if (obj.primitives.size() > 1) ImGui::TextDisabled("The Voter tries primitives in this order.");
  }
  if (sel.object >= 0 && sel.primitive >= 0) {
    const Primitive& prim = objects[sel.object].primitives[sel.primitive];
    std::string title = "Dimensions of ";
    title.append(prim.name).append(" (w_h)");
    section(title.c_str());
    names.clear();
    weights.clear();
    double sum = 0;
    const auto dn = dimension_names(prim.kind);
    for (std::size_t d = 0; d < prim.dimensions.size() && d < dn.size(); ++d) {
      names.emplace_back(dn[d]);
      weights.push_back(prim.dimensions[d].weight);
      sum += prim.dimensions[d].weight;
    }
    if (ui.rank_mode) {
      rank_list("dims", names, weights, emit(WeightLevel::dimension, sel.object, sel.primitive));
    } else {
      for (int d = 0; d < static_cast<int>(names.size()); ++d) {
        ImGui::PushID(2000 + d);
        weight_slider(names[d], weights[d], queue,
                      {WeightLevel::dimension, sel.object, sel.primitive, d, 0});
        ImGui::PopID();
      }
    }
    // The Voter normalises w_h to sum to 1: show each dimension's real share.
    std::string shares = "share of the size score:";
    for (std::size_t d = 0; d < names.size(); ++d) {
      const double share = sum > 0 ? weights[d] / sum : 1.0 / static_cast<double>(names.size());
      shares.append(" ").append(names[d]).append(" ");
      shares.append(std::to_string(static_cast<int>(share * 100 + 0.5))).append("%");
    }
    ImGui::TextWrapped("%s", shares.c_str());
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace annex::authoring
