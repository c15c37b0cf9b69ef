# The Python module (python/, docs/python.md): build/python/dynamap/ holds the package's .py
# files (copied from python/dynamap/), the extension _core and the ICP module it loads beside
# itself, so that PYTHONPATH=build/python imports it from the build tree. `make demo` builds only
# the dynamap program, never this.
set(DYNAMAP_PY_DIR ${CMAKE_CURRENT_BINARY_DIR}/python/dynamap)
pybind11_add_module(dynamap_python NO_EXTRAS python/src/core.cpp python/src/stream.cpp)
set_target_properties(dynamap_python PROPERTIES OUTPUT_NAME _core
  LIBRARY_OUTPUT_DIRECTORY ${DYNAMAP_PY_DIR})
target_link_libraries(dynamap_python PRIVATE dynamap_cli)
target_include_directories(dynamap_python PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src/app)
target_compile_options(dynamap_python PRIVATE ${DYNAMAP_WARNINGS})
add_custom_command(TARGET dynamap_python POST_BUILD
  COMMAND ${CMAKE_COMMAND} -E copy_if_different $<TARGET_FILE:dynamap_icp> ${DYNAMAP_PY_DIR}/)

file(GLOB DYNAMAP_PY_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/python/dynamap/*.py)
set(DYNAMAP_PY_COPIES "")
foreach(f ${DYNAMAP_PY_SOURCES})
  get_filename_component(name ${f} NAME)
  add_custom_command(OUTPUT ${DYNAMAP_PY_DIR}/${name}
    COMMAND ${CMAKE_COMMAND} -E copy ${f} ${DYNAMAP_PY_DIR}/${name} DEPENDS ${f})
  list(APPEND DYNAMAP_PY_COPIES ${DYNAMAP_PY_DIR}/${name})
endforeach()
add_custom_target(dynamap_python_files ALL DEPENDS ${DYNAMAP_PY_COPIES})
add_dependencies(dynamap_python dynamap_python_files)

# pytest (python/tests/), one ctest entry per file, each with the build's module and program.
if(DYNAMAP_TESTS_ON)
  foreach(t bindings stream docs batch cluster)
    add_test(NAME Python.${t}
      COMMAND ${DYNAMAP_PYTHON_EXECUTABLE} -m pytest -q -p no:cacheprovider
              ${CMAKE_CURRENT_SOURCE_DIR}/python/tests/test_${t}.py)
    set_tests_properties(Python.${t} PROPERTIES TIMEOUT 900 ENVIRONMENT
      "PYTHONDONTWRITEBYTECODE=1;PYTHONPATH=${CMAKE_CURRENT_BINARY_DIR}/python;DYNAMAP_EXE=$<TARGET_FILE:dynamap>;DYNAMAP_SOURCE_DIR=${CMAKE_CURRENT_SOURCE_DIR}")
  endforeach()
  set_tests_properties(Python.cluster PROPERTIES RUN_SERIAL ON)
endif()
