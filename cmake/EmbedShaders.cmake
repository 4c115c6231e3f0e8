# vts_embed_shaders(TARGET name FILES a.glsl b.glsl ...)
# Generates a C++ source holding each shader as a string constant named after
# its file (raster.vert -> vts::shaders::raster_vert), so binaries never look
# for shaders on disk.
function(vts_embed_shaders)
  cmake_parse_arguments(ES "" "TARGET" "FILES" ${ARGN})
  set(out_cpp ${CMAKE_CURRENT_BINARY_DIR}/embedded_shaders.cpp)
  set(out_h ${CMAKE_CURRENT_BINARY_DIR}/shaders/embedded.h)
  set(inputs)
  foreach(f ${ES_FILES})
    list(APPEND inputs ${CMAKE_CURRENT_SOURCE_DIR}/${f})
  endforeach()
  # A CMake list does not survive a command line; pass the inputs '|'-joined.
  string(REPLACE ";" "|" inputs_arg "${inputs}")
  add_custom_command(
    OUTPUT ${out_cpp} ${out_h}
    COMMAND ${CMAKE_COMMAND} -DOUT_CPP=${out_cpp} -DOUT_H=${out_h}
            "-DINPUTS=${inputs_arg}" -P ${PROJECT_SOURCE_DIR}/cmake/EmbedShadersScript.cmake
    DEPENDS ${inputs} ${PROJECT_SOURCE_DIR}/cmake/EmbedShadersScript.cmake
    COMMENT "Embedding shaders"
    VERBATIM)
  add_library(${ES_TARGET} STATIC ${out_cpp} ${out_h})
  target_include_directories(${ES_TARGET} PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_BINARY_DIR}>)
endfunction()
