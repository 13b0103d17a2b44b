// annex-author: the HapticModelGenerator editor (docs/editor.md). The loop is the one
// of Dear ImGui's examples/example_glfw_opengl3/main.cpp; the editor lives in the
// panels (one per file) and EditorApp, which applies their commands after the frame.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "editor_app.h"
#include "panels.h"
#include "renderer.h"

namespace {

void glfw_error(int code, const char* description) {
  std::fprintf(stderr, "annex-author: GLFW error %d: %s\n", code, description);
}

void setup_style(ImGuiIO& io) {
  ImGui::StyleColorsDark();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 0.f;
  style.FrameRounding = 3.f;
  style.GrabRounding = 3.f;
  style.WindowBorderSize = 1.f;
  style.ItemSpacing = ImVec2(8, 5);
  const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  std::error_code ec;
  if (std::filesystem::exists(font, ec)) io.Fonts->AddFontFromFileTTF(font, 15.f);
  io.IniFilename = nullptr;  // the layout is fixed; nothing to remember between runs
}

}  // namespace

int main(int argc, char** argv) {
  int exit_code = 0;
  const auto options = annex::authoring::parse_options(argc, argv, exit_code);
  if (!options) return exit_code;

  glfwSetErrorCallback(glfw_error);
  if (!glfwInit()) return 1;
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, options->samples);
  // Opened by a person, the window fits the screen's work area (a 1280x720 laptop
  // screen would cut the 1600x900 default's right panels); scripts keep their --size.
  int width = options->width, height = options->height;
  if (options->script_path.empty())
    if (GLFWmonitor* monitor = glfwGetPrimaryMonitor()) {
      int x = 0, y = 0, w = 0, h = 0;
      glfwGetMonitorWorkarea(monitor, &x, &y, &w, &h);
      if (w > 0 && h > 0) width = std::min(width, w), height = std::min(height, h);
    }
  GLFWwindow* window = glfwCreateWindow(width, height, "Annex author", nullptr, nullptr);
  if (window == nullptr) {
    std::fprintf(stderr, "annex-author: error: cannot open an OpenGL 3.3 core window\n");
    glfwTerminate();
    return 1;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(options->script_path.empty() ? 1 : 0);  // scripts run as fast as they can

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  setup_style(io);
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  int code = 0;
  try {
    annex::authoring::Renderer renderer;
    if (annex::Status s = renderer.init(); !s) {
      std::fprintf(stderr, "annex-author: error: %s\n", s.error().format().c_str());
      code = 1;
    } else {
      if (options->samples > 0) glEnable(GL_MULTISAMPLE);
      annex::authoring::EditorApp app(*options);
      while (!app.done()) {
        glfwPollEvents();
        if (glfwWindowShouldClose(window)) {
          glfwSetWindowShouldClose(window, GLFW_FALSE);
          app.request_quit();  // asks about unsaved changes first
        }
        app.before_frame(renderer);

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        annex::authoring::draw_editor(app.doc(), app.ui(), app.queue());
        ImGui::Render();

        int fb_w = 0, fb_h = 0, win_w = 0, win_h = 0;
        glfwGetFramebufferSize(window, &fb_w, &fb_h);
        glfwGetWindowSize(window, &win_w, &win_h);
        glViewport(0, 0, fb_w, fb_h);
        glClearColor(0.11f, 0.11f, 0.12f, 1.f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        renderer.draw(app.doc(), app.ui(), fb_w, fb_h,
                      win_w > 0 ? static_cast<float>(fb_w) / win_w : 1.f);
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        app.after_render(fb_w, fb_h);
        glfwSwapBuffers(window);

        app.apply_queue(renderer);  // edits happen between frames
      }
      code = app.exit_code();
    }
  } catch (const std::exception& e) {
    // Only programmer errors throw; end with one clear line.
    std::fprintf(stderr, "annex-author: internal error: %s\n", e.what());
    code = 1;
  }

  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return code;
}
