# install(EXPORT) of the libraries, found by `find_package(dorado)` (tests/consumer builds a project
# against an installed copy): dorado::core and dorado::odometry (Eigen alone; all that
# DORADO_CORE_ONLY builds), and otherwise dorado::mapping, loops, frontend, io and config too. Included
# once every library's target exists. The libraries are static: their private third-party links
# reach the consumer as $<LINK_ONLY:...>, so doradoConfig.cmake finds those packages again.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

if(DORADO_CORE_ONLY)
  set(DORADO_EXPORTED_MODULES core odometry)
  set(DORADO_HAVE_LIBRARIES OFF)
  foreach(backend ROS1 ROSBAG2 HDF5)
    set(DORADO_HAVE_${backend} OFF)
  endforeach()
else()
  set(DORADO_EXPORTED_MODULES core odometry mapping loops frontend io config)
  set(DORADO_HAVE_LIBRARIES ON)
endif()
set(DORADO_EXPORTED_TARGETS dorado_warnings)
foreach(module ${DORADO_EXPORTED_MODULES})
  target_include_directories(dorado_${module} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/${module}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  set_target_properties(dorado_${module} PROPERTIES EXPORT_NAME ${module})
  add_library(dorado::${module} ALIAS dorado_${module})
  list(APPEND DORADO_EXPORTED_TARGETS dorado_${module})
  # ros1_cloud_view.hpp includes ROS1's sensor_msgs: installed with the ROS1 reader only.
  set(exclude)
  if(NOT DORADO_HAVE_ROS1)
    set(exclude PATTERN ros1_cloud_view.hpp EXCLUDE)
  endif()
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
    ${exclude})
endforeach()
# dorado_warnings is linked privately (static libraries list it as $<LINK_ONLY:...>): export it
# too, as an empty interface for the consumer.
set_target_properties(dorado_warnings PROPERTIES EXPORT_NAME warnings)
# A sanitized build's static libraries call the sanitizers' runtime: whoever links them needs it,
# so the exported target says so (tests/consumer links an installed sanitized build).
if(DORADO_SANITIZE)
  target_link_options(dorado_core INTERFACE -fsanitize=address,undefined)
endif()
install(TARGETS ${DORADO_EXPORTED_TARGETS} EXPORT doradoTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT doradoTargets NAMESPACE dorado:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dorado)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/doradoConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/doradoConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dorado)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/doradoConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/doradoConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/doradoConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/doradoRosbagStorage.cmake DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dorado)
