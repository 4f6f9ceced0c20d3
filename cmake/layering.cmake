# What each target may include, and its warnings.
#
# Sources include each other by library folder ("fit/targets.hpp",
# "reference/reference.hpp"). A target sees only its own folder and those of the
# libraries it links: sglab_own_headers gives it an include root that holds one
# entry, a link to its folder, and linking a library brings that library's root
# along (PUBLIC). So an include that runs against the layering (validate/
# including fit/, report/ including export/) fails to compile instead of
# silently working.

# sglab_own_headers(TARGET FOLDER PUBLIC|PRIVATE): TARGET's sources and, for
# PUBLIC, those of every target linking it may include "FOLDER/...".
function(sglab_own_headers target folder scope)
  set(root ${PROJECT_BINARY_DIR}/include_roots/${folder})
  file(MAKE_DIRECTORY ${root})
  file(CREATE_LINK ${PROJECT_SOURCE_DIR}/${folder} ${root}/${folder} SYMBOLIC)
  target_include_directories(${target} ${scope} $<BUILD_INTERFACE:${root}>)
endfunction()

# sglab_warnings(TARGET): the warnings every sglab target builds with, errors
# under SGLAB_WERROR (CI).
function(sglab_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wconversion
    $<$<BOOL:${SGLAB_WERROR}>:-Werror>)
endfunction()
