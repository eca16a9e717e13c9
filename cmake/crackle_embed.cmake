# crackle_embed_files(TARGET tgt FUNCTION name BASE dir GLOB pattern...)
# Embeds text files (presets, later shaders) into the binary as raw-string literals so that
# `crackle` runs from any directory. The generated function returns the embedded files as
# {relative name without extension, text} pairs (see core/embedded.hpp).
set(CRACKLE_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/crackle_embed_script.cmake)

function(crackle_embed_files)
  cmake_parse_arguments(ARG "" "TARGET;FUNCTION;BASE" "GLOBS" ${ARGN})
  set(files)
  foreach(pattern IN LISTS ARG_GLOBS)
    file(GLOB_RECURSE found CONFIGURE_DEPENDS "${ARG_BASE}/${pattern}")
    list(APPEND files ${found})
  endforeach()
  list(SORT files)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_${ARG_FUNCTION}.cpp)
  string(REPLACE ";" "|" files_arg "${files}")
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DFUNCTION=${ARG_FUNCTION} -DBASE=${ARG_BASE}
            "-DFILES=${files_arg}" -P ${CRACKLE_EMBED_SCRIPT}
    DEPENDS ${files} ${CRACKLE_EMBED_SCRIPT}
    COMMENT "Embedding ${ARG_FUNCTION}"
    VERBATIM)
  target_sources(${ARG_TARGET} PRIVATE ${out})
endfunction()
