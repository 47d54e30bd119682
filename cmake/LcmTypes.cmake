# Generates C++ headers and a Java jar from the .lcm files at build time.
# Nothing generated is committed: build/gen/ holds it all.
#   target evade_lcmtypes      INTERFACE library with the C++ include path
#   target evade_lcmtypes_jar  build/share/java/evade_lcmtypes.jar (for lcm-spy)
function(evade_lcmtypes lcm_dir)
  find_program(LCM_GEN lcm-gen REQUIRED)
  find_package(Java COMPONENTS Development)
  file(GLOB lcm_files ${lcm_dir}/*.lcm)
  list(SORT lcm_files)

  set(cpp_out ${CMAKE_BINARY_DIR}/gen/cpp)
  set(java_out ${CMAKE_BINARY_DIR}/gen/java)
  set(cpp_headers)
  set(java_sources)
  foreach(f ${lcm_files})
    get_filename_component(base ${f} NAME_WE)
    string(REGEX REPLACE "^evade_" "" type ${base})
    list(APPEND cpp_headers ${cpp_out}/evade/${type}.hpp)
    list(APPEND java_sources ${java_out}/evade/${type}.java)
  endforeach()

  add_custom_command(
    OUTPUT ${cpp_headers}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${cpp_out}
    COMMAND ${LCM_GEN} --cpp --cpp-hpath ${cpp_out} ${lcm_files}
    DEPENDS ${lcm_files}
    COMMENT "lcm-gen: C++ types"
    VERBATIM)
  add_custom_target(evade_lcmtypes_cpp DEPENDS ${cpp_headers})
  add_library(evade_lcmtypes INTERFACE)
  target_include_directories(evade_lcmtypes INTERFACE ${cpp_out})
  target_link_libraries(evade_lcmtypes INTERFACE PkgConfig::LCM)
  add_dependencies(evade_lcmtypes evade_lcmtypes_cpp)

  set(LCM_JAR /usr/share/java/lcm.jar)
  if(Java_JAVAC_EXECUTABLE AND Java_JAR_EXECUTABLE AND EXISTS ${LCM_JAR})
    set(jar ${CMAKE_BINARY_DIR}/share/java/evade_lcmtypes.jar)
    set(classes ${CMAKE_BINARY_DIR}/gen/java_classes)
    add_custom_command(
      OUTPUT ${jar}
      COMMAND ${CMAKE_COMMAND} -E remove_directory ${java_out}
      COMMAND ${CMAKE_COMMAND} -E remove_directory ${classes}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${java_out}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${classes}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/share/java
      COMMAND ${LCM_GEN} --java --jpath ${java_out} ${lcm_files}
      COMMAND ${Java_JAVAC_EXECUTABLE} -nowarn -source 8 -target 8 -cp ${LCM_JAR}
              -d ${classes} ${java_sources}
      COMMAND ${Java_JAR_EXECUTABLE} cf ${jar} -C ${classes} .
      DEPENDS ${lcm_files}
      COMMENT "lcm-gen + javac: build/share/java/evade_lcmtypes.jar"
      VERBATIM)
    add_custom_target(evade_lcmtypes_jar ALL DEPENDS ${jar})
  else()
    message(WARNING "javac, jar or ${LCM_JAR} missing: no Java types for lcm-spy")
  endif()
endfunction()
