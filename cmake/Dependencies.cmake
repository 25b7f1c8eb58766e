# Every third-party package, found through its own CMake config where it has one.
# scripts/install_deps.sh installs them all on Debian 12.

find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(Threads REQUIRED)
# oneTBB runs ParallelFor (core/parallel.cpp) on its shared worker pool.
find_package(TBB REQUIRED)
find_package(OpenSSL REQUIRED)  # SHA-256 of MAVLink 2 packet signing
# Optional: the live RealSense backend is built only when librealsense2 is installed (it
# is not in Debian; README, Hardware, says how to add it). .bag replay does not need it.
find_package(realsense2 QUIET)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(spdlog REQUIRED)
find_package(fmt REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(urdfdom REQUIRED)
find_package(fcl REQUIRED)
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs dnn calib3d)
find_package(VISP REQUIRED COMPONENTS visp_core visp_vision visp_vs visp_detection visp_mbt)
find_package(apriltag REQUIRED)
find_package(embree 3 REQUIRED)
# Qhull's config exports Qhull::qhull_r (reentrant C library, used by grasp quality).
find_package(Qhull REQUIRED)
find_package(orocos_kdl REQUIRED)
# PCL's config needs MPI's C target before it is found.
find_package(MPI COMPONENTS C)
find_package(PCL 1.12 REQUIRED COMPONENTS common io kdtree search features registration filters)
# RealSense .bag files are read with ROS 1's bag library (Debian's librosbag-storage-dev and the
# message packages). Their configs run python3 (through ament): the system one, whose modules
# they need, not a python3 that happens to come first on PATH.
set(PYTHON_EXECUTABLE /usr/bin/python3)
set(Python3_EXECUTABLE /usr/bin/python3)
find_package(rosbag_storage REQUIRED)
foreach(_ros_package sensor_msgs geometry_msgs std_msgs diagnostic_msgs rostime
        roscpp_serialization cpp_common)
  find_package(${_ros_package} REQUIRED)
endforeach()
if(NOT TARGET aerograsp_ros_bag)
  add_library(aerograsp_ros_bag INTERFACE)
  target_include_directories(aerograsp_ros_bag SYSTEM INTERFACE
    ${rosbag_storage_INCLUDE_DIRS} ${sensor_msgs_INCLUDE_DIRS} ${geometry_msgs_INCLUDE_DIRS}
    ${std_msgs_INCLUDE_DIRS} ${diagnostic_msgs_INCLUDE_DIRS} ${rostime_INCLUDE_DIRS}
    ${roscpp_serialization_INCLUDE_DIRS} ${cpp_common_INCLUDE_DIRS})
  # rostime, roscpp_serialization and cpp_common are not brought in by rosbag_storage's config.
  target_link_libraries(aerograsp_ros_bag INTERFACE ${rosbag_storage_LIBRARIES}
    ${rostime_LIBRARIES} ${roscpp_serialization_LIBRARIES} ${cpp_common_LIBRARIES})
endif()

# The reports' interactive charts: Chart.js from Debian's libjs-chart.js, built into the program
# (app/CMakeLists.txt) so that a report page needs no network and no file beside it.
find_file(AEROGRASP_CHARTJS chart.min.js PATHS /usr/share/javascript/chart.js NO_DEFAULT_PATH)
if(NOT AEROGRASP_CHARTJS)
  message(FATAL_ERROR "chart.min.js not found in /usr/share/javascript/chart.js: install the Debian "
                      "package libjs-chart.js (scripts/install_deps.sh)")
endif()

# ROS 2 topics over DDS (ros2/): Cyclone DDS, whose idlc generates the message types.
find_package(CycloneDDS REQUIRED)

if(AEROGRASP_BUILD_TESTS)
  find_package(GTest REQUIRED)
  find_package(benchmark REQUIRED)
  # The independent ROS 2 peer of the tests (tests/peers/ros2): Fast DDS, dynamic types.
  find_package(fastrtps REQUIRED)
  find_package(fastcdr REQUIRED)
endif()

# urdfdom's config exports plain variables; wrap them in one target.
if(NOT TARGET aerograsp_urdfdom)
  add_library(aerograsp_urdfdom INTERFACE)
  target_include_directories(aerograsp_urdfdom INTERFACE ${urdfdom_INCLUDE_DIRS})
  target_link_libraries(aerograsp_urdfdom INTERFACE ${urdfdom_LIBRARIES})
endif()
