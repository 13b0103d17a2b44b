# annex_renderer: the Renderer (OpenGL 3.3 core through EGL surfaceless or GLFW) and
# the HMD config. Separate from annex_runtime so the GL, EGL and GLFW libraries are
# linked only where rendering is used; nothing of them shows in renderer.h.
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)
find_package(glfw3 3.3 REQUIRED)
add_library(annex_renderer
  ${CMAKE_CURRENT_LIST_DIR}/src/renderer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/renderer_config.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/renderer_png.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/renderer_shapes.cpp
)
add_library(annex::renderer ALIAS annex_renderer)
# renderer.h only needs frame.h of the runtime headers, so no link to annex_runtime
# (and its PCL). The HMD config reuses the formats' line lexer.
target_include_directories(annex_renderer PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include)
target_link_libraries(annex_renderer
  PUBLIC annex::common annex::formats annex::mesh
  PRIVATE OpenGL::OpenGL OpenGL::EGL glfw annex::flags)

target_sources(annex-runtime PRIVATE ${CMAKE_CURRENT_LIST_DIR}/app/cmd_render.cpp
                                      ${CMAKE_CURRENT_LIST_DIR}/app/label_points.cpp)
target_link_libraries(annex-runtime PRIVATE annex::renderer)
