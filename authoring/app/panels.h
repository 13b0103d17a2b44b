#pragma once
// One panel per file, each drawing from the document and asking for edits through
// the queue (STYLE.md, "The editor").

#include "annex/authoring/editor_document.h"
#include "ui_state.h"
#include "view.h"

namespace annex::authoring {

void draw_menu_bar(const EditorDocument& doc, UiState& ui, CommandQueue& queue);
// The side panels, each in its rectangle of ui.layout.
void draw_outline(const EditorDocument& doc, UiState& ui, CommandQueue& queue);
void draw_inspector(const EditorDocument& doc, UiState& ui, CommandQueue& queue);
void draw_priorities(const EditorDocument& doc, UiState& ui, CommandQueue& queue);
void draw_limits(const EditorDocument& doc, UiState& ui, CommandQueue& queue);
void draw_match_preview(const EditorDocument& doc, UiState& ui, CommandQueue& queue);
// Camera input, viewport handles, box selection, overlay labels (no GL: ImGui draw lists).
void draw_viewport(const EditorDocument& doc, UiState& ui, CommandQueue& queue);
// Selects the vertices of the selected object's mesh whose projections fall in the
// screen rectangle a-b (what Ctrl + drag does).
// `through`: every surface inside the rectangle, back and hidden parts too (X-ray),
// instead of only what the camera sees.
void select_box(const EditorDocument& doc, UiState& ui, ImVec2 a, ImVec2 b, bool through = false);
// File dialog, unsaved-changes and recovery prompts.
void draw_dialogs(const EditorDocument& doc, UiState& ui, CommandQueue& queue);

// Opens the file chooser for `purpose` in a sensible folder.
void open_file_dialog(UiState& ui, AppAction::Kind purpose, const EditorDocument& doc);

// A labelled separator (ImGui 1.86 has no SeparatorText).
void section(const char* title);
// The next window fills `r` (the fixed layout: 1.86 has no docking).
void place_next_window(const Rect& r);

// All of the above for one frame, in the fixed layout.
void draw_editor(const EditorDocument& doc, UiState& ui, CommandQueue& queue);

}  // namespace annex::authoring
