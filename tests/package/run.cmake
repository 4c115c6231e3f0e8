# CTest: install the build into a fresh prefix, then configure, build and run
# the consumer projects against it (cmake -DBUILD=... -DSRC=... -DWORK=... -P).
file(REMOVE_RECURSE ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix --component dev)
# The tracker alone: every other dependency of vts made unfindable.
set(no_deps)
foreach(p TBB nlohmann_json yaml-cpp OpenEXR embree assimp OpenImageIO PkgConfig)
  list(APPEND no_deps -DCMAKE_DISABLE_FIND_PACKAGE_${p}=ON)
endforeach()
foreach(proj tracker_only full)
  set(extra)
  if(proj STREQUAL "tracker_only")
    set(extra ${no_deps})
  endif()
  run(${CMAKE_COMMAND} -S ${SRC}/${proj} -B ${WORK}/${proj} -G Ninja -DCMAKE_BUILD_TYPE=Release
      -DCMAKE_PREFIX_PATH=${WORK}/prefix ${extra})
  run(${CMAKE_COMMAND} --build ${WORK}/${proj})
  run(${WORK}/${proj}/consumer)
endforeach()

# The Python package, installed: importable from the prefix alone.
if(PYTHON)
  run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix --component python)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${WORK}/prefix/${PYDIR}
                          ${PYTHON} -c "import vts, numpy; s = vts.scan('fillet', profiles=2); print(vts.__file__, s.y.shape)"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "^${WORK}/prefix/${PYDIR}/vts/__init__.py \\(2, 512\\)")
    message(FATAL_ERROR "installed Python package: ${out}${err}")
  endif()
  message(STATUS "${out}")
endif()
