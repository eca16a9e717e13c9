# INTERFACE target carrying the project's warning flags; link it PRIVATE.
add_library(crackle_warnings INTERFACE)
add_library(crackle::warnings ALIAS crackle_warnings)
target_compile_options(crackle_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wfloat-conversion -Wnon-virtual-dtor)
if(CRACKLE_WERROR)
  target_compile_options(crackle_warnings INTERFACE -Werror)
endif()
