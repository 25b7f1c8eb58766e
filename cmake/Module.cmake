# aerograsp_module(NAME SOURCES ... DEPS ...): one library target per module,
# named aerograsp_<NAME>, with the repository root on its include path so that
# headers are included as "core/arm_model.h".
function(aerograsp_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(aerograsp_${name} STATIC ${ARG_SOURCES})
  target_include_directories(aerograsp_${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(aerograsp_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  aerograsp_warnings(aerograsp_${name})
endfunction()

function(aerograsp_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic
                         $<$<COMPILE_LANGUAGE:CXX>:-Wno-deprecated-copy>)
  if(AEROGRASP_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
