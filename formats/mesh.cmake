# annex_mesh: visual meshes read with assimp (mesh_io.h), shared by the runtime's
# Renderer and the editor. A separate target so annex::formats stays free of assimp.
find_package(assimp REQUIRED)
add_library(annex_mesh ${CMAKE_CURRENT_LIST_DIR}/src/mesh_io.cpp)
add_library(annex::mesh ALIAS annex_mesh)
target_include_directories(annex_mesh PUBLIC ${CMAKE_CURRENT_LIST_DIR}/include)
target_link_libraries(annex_mesh PUBLIC annex::common PRIVATE assimp::assimp annex::flags)
