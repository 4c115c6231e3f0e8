# `cmake --install build --prefix P`: the libraries, their headers, the
# executables and a CMake package (P/lib/cmake/vts/vtsConfig.cmake) exporting
# vts::tracker, vts::stripe, vts::sensor, vts::render and the rest. The tracker
# and stripe are their own export set so that find_package(vts COMPONENTS
# tracker stripe) needs only Eigen (stripe needs nothing).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(VTS_LIBS common tracker stripe robot trackio sensor shaders render plot pipeline)
foreach(t ${VTS_LIBS})
  set_target_properties(vts_${t} PROPERTIES EXPORT_NAME ${t})
  add_library(vts::${t} ALIAS vts_${t})
endforeach()

set(VTS_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/vts)
install(TARGETS vts_tracker vts_stripe EXPORT vtsTrackerTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(TARGETS vts_common vts_robot vts_trackio vts_sensor vts_shaders vts_render vts_plot vts_pipeline
        EXPORT vtsTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(EXPORT vtsTrackerTargets NAMESPACE vts:: DESTINATION ${VTS_CMAKE_DIR} COMPONENT dev)
install(EXPORT vtsTargets NAMESPACE vts:: DESTINATION ${VTS_CMAKE_DIR} COMPONENT dev)
foreach(dir common tracker stripe robot trackio sensor render plot pipeline)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/vts/${dir}
          COMPONENT dev FILES_MATCHING PATTERN "*.h")
endforeach()

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/vtsConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/vtsConfig.cmake INSTALL_DESTINATION ${VTS_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/vtsConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/vtsConfig.cmake ${PROJECT_BINARY_DIR}/vtsConfigVersion.cmake
        DESTINATION ${VTS_CMAKE_DIR} COMPONENT dev)

install(TARGETS vts RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT bin)
if(TARGET vts-view)
  install(TARGETS vts-view RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT bin)
endif()
