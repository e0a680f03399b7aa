# rosbag_storage::rosbag_storage, after find_package(rosbag_storage): its catkin-style config sets
# variables (no target) and leaves out the ROS core libraries its headers need, so one imported
# target wraps both. GLOBAL: dorado_sim writes bags. Used by io/CMakeLists.txt and installed for
# doradoConfig.cmake (an installed static dorado_io links it).
if(NOT TARGET rosbag_storage::rosbag_storage)
  add_library(rosbag_storage::rosbag_storage INTERFACE IMPORTED GLOBAL)
  target_include_directories(rosbag_storage::rosbag_storage SYSTEM INTERFACE ${rosbag_storage_INCLUDE_DIRS})
  target_link_libraries(rosbag_storage::rosbag_storage INTERFACE
    ${rosbag_storage_LIBRARIES} rostime roscpp_serialization cpp_common)
endif()
