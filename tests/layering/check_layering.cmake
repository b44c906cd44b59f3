# ctest: the layers of src/bouguer are enforced by the build (src/bouguer/CMakeLists.txt): a source of
# a layer, compiled with that layer's include root, can include the headers of the layers below it
# and fails to compile when it includes one above it.
# cmake -DCXX=<compiler> -DLAYERS=<build>/layers -DWORK=<scratch dir> -P check_layering.cmake
file(MAKE_DIRECTORY ${WORK})

function(compile_with layer header result_var output_var)
  set(source ${WORK}/${layer}_includes.cpp)
  file(WRITE ${source} "#include \"${header}\"\nint main() { return 0; }\n")
  execute_process(COMMAND ${CXX} -std=c++20 -fsyntax-only -I${LAYERS}/${layer} ${source}
                  RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(${result_var} ${result} PARENT_SCOPE)
  set(${output_var} "${out}${err}" PARENT_SCOPE)
endfunction()

# Downward: a layer sees itself and what is below it.
foreach(pair
    "bouguer_spectra;bouguer/core/csv.h"
    "bouguer_media;bouguer/media/medium.h"
    "bouguer_lights;bouguer/lights/environment.h"
    "bouguer_integrators;bouguer/scene/compile.h"
    "bouguer_integrators;bouguer/render/film.h")
  list(GET pair 0 layer)
  list(GET pair 1 header)
  compile_with(${layer} ${header} result out)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${layer} cannot include ${header}, which is below it:\n${out}")
  endif()
endforeach()

# Upward: each include that ran back up before the layers were enforced fails to build.
foreach(pair
    "bouguer_spectra;bouguer/io/image_io.h"
    "bouguer_media;bouguer/render/film.h"
    "bouguer_materials;bouguer/render/camera.h"
    "bouguer_lights;bouguer/scene/description.h"
    "bouguer_io;bouguer/render/film.h"
    "bouguer_scene;bouguer/render/integrator.h"
    "bouguer_render;bouguer/integrators/integrators.h"
    "bouguer_geometry;bouguer/io/image_io.h")
  list(GET pair 0 layer)
  list(GET pair 1 header)
  compile_with(${layer} ${header} result out)
  if(result EQUAL 0)
    message(FATAL_ERROR "${layer} includes ${header}, a layer above it, and it compiled: layers not enforced")
  endif()
  # GCC and clang both say "<header>: No such file"; any other failure is not the layering's.
  string(FIND "${out}" "${header}: No such file" missing)
  if(missing EQUAL -1)
    message(FATAL_ERROR "${layer} including ${header} failed, but not because the header is out of reach:\n${out}")
  endif()
endforeach()
message(STATUS "layers enforced: 5 downward includes compile, 8 upward ones fail")
