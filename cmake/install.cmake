# install(EXPORT) of the libraries that embed with Eigen alone: dorado::core and dorado::odometry,
# found by `find_package(dorado)` (tests/consumer builds a project against an installed copy).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

foreach(module core odometry)
  target_include_directories(dorado_${module} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/${module}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  set_target_properties(dorado_${module} PROPERTIES EXPORT_NAME ${module})
  add_library(dorado::${module} ALIAS dorado_${module})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
# dorado_warnings is linked privately (static libraries list it as $<LINK_ONLY:...>): export it
# too, as an empty interface for the consumer.
set_target_properties(dorado_warnings PROPERTIES EXPORT_NAME warnings)
# A sanitized build's static libraries call the sanitizers' runtime: whoever links them needs it,
# so the exported target says so (tests/consumer links an installed sanitized build).
if(DORADO_SANITIZE)
  target_link_options(dorado_core INTERFACE -fsanitize=address,undefined)
endif()
install(TARGETS dorado_core dorado_odometry dorado_warnings EXPORT doradoTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT doradoTargets NAMESPACE dorado:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dorado)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/doradoConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/doradoConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dorado)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/doradoConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/doradoConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/doradoConfigVersion.cmake DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dorado)
