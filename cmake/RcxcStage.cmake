# rcxc_stage(NAME): one static library per pipeline folder, built from every
# .cpp in that folder (globbed so that adding a file needs no CMake edit),
# with the project's warnings and the repository root as the include root
# (headers are included as "stage/file.h"). A folder with no sources yet is
# an interface library, so dependents can already name it.
function(rcxc_stage name)
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  if(sources)
    add_library(rcxc_${name} STATIC ${sources})
    target_include_directories(rcxc_${name} PUBLIC ${PROJECT_SOURCE_DIR} ${PROJECT_BINARY_DIR})
    target_link_libraries(rcxc_${name} PRIVATE rcxc_warnings)
  else()
    add_library(rcxc_${name} INTERFACE)
    target_include_directories(rcxc_${name} INTERFACE ${PROJECT_SOURCE_DIR})
  endif()
endfunction()

# Links a stage library to its dependencies whatever kind it currently is.
function(rcxc_stage_link name)
  get_target_property(type rcxc_${name} TYPE)
  if(type STREQUAL "INTERFACE_LIBRARY")
    target_link_libraries(rcxc_${name} INTERFACE ${ARGN})
  else()
    target_link_libraries(rcxc_${name} PUBLIC ${ARGN})
  endif()
endfunction()
