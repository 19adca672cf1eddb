# Included by ctest after the GL tests discovered with the prefix "Zink." (tests/CMakeLists.txt), whose names
# gtest_discover_tests leaves in firn_gl_zink_tests: each runs on Mesa's software path (LIBGL_ALWAYS_SOFTWARE=1)
# with Zink as its Gallium driver, over lavapipe (docs/platform.md, A second driver: Zink).
# Zink.Context.TheRendererIsTheDriverMesaWasAskedFor checks that Mesa gave Zink.
if(NOT firn_gl_zink_tests)
  message(WARNING "no Zink.* GL tests were discovered: is firn_gl_tests built?")
endif()
foreach(test IN LISTS firn_gl_zink_tests)
  set_tests_properties("${test}" PROPERTIES ENVIRONMENT "LIBGL_ALWAYS_SOFTWARE=1;GALLIUM_DRIVER=zink")
endforeach()
