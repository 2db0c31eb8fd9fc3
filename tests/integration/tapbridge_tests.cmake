# tapbridge integration tests (included from tests/integration/CMakeLists.txt).
sitlnet_add_gtest(tapbridge_integration_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/tapbridge_test_util.cc
          ${CMAKE_CURRENT_LIST_DIR}/tapbridge_traffic_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/tapbridge_topology_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/tapbridge_robustness_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/tapbridge_lockstep_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/tapbridge_qos_test.cc
          ${CMAKE_CURRENT_LIST_DIR}/realtime_judge.cc
  LIBS sitlnet_tapbridge
  LABELS integration)
target_include_directories(tapbridge_integration_test PRIVATE ${CMAKE_SOURCE_DIR})
add_dependencies(tapbridge_integration_test sitlnet)
