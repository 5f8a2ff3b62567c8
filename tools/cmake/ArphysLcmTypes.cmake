# arphys_add_lcm_types(<target> FILES <a.lcm>... [JAR <name>])
#
# Runs lcm-gen on every .lcm file at build time (outputs live in the build tree
# and are never committed) and defines:
#   <target>       INTERFACE library: generated C++ headers + LCM link flags
#   <target>_jar   (when JAR is given and Java is found) a jar for lcm-spy
#
# Debian's LCM 1.3.1 has no lcmUtilities.cmake, hence this function.
find_program(LCM_GEN_EXECUTABLE lcm-gen REQUIRED)
set(ARPHYS_HARDEN_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/ArphysHardenLcmDecode.cmake)

function(arphys_add_lcm_types target)
  cmake_parse_arguments(ARG "" "JAR" "FILES" ${ARGN})
  if(NOT ARG_FILES)
    message(FATAL_ERROR "arphys_add_lcm_types(${target}): no FILES given")
  endif()
  set(cpp_dir ${CMAKE_CURRENT_BINARY_DIR}/lcmgen/cpp)
  set(java_dir ${CMAKE_CURRENT_BINARY_DIR}/lcmgen/java)
  set(headers "")
  set(java_sources "")
  foreach(lcm_file IN LISTS ARG_FILES)
    get_filename_component(abs ${lcm_file} ABSOLUTE)
    # One type per file, and the file is named after the type: read the
    # package from the file so the output path is known at configure time.
    file(STRINGS ${abs} package_line REGEX "^[ \t]*package[ \t]+[A-Za-z0-9_]+[ \t]*;")
    string(REGEX REPLACE "^[ \t]*package[ \t]+([A-Za-z0-9_]+).*" "\\1" package "${package_line}")
    if(NOT package)
      message(FATAL_ERROR "${abs}: no 'package <name>;' line (every arphys type is package-named)")
    endif()
    get_filename_component(type_name ${abs} NAME_WE)
    set(hpp ${cpp_dir}/${package}/${type_name}.hpp)
    set(java ${java_dir}/${package}/${type_name}.java)
    add_custom_command(
      OUTPUT ${hpp}
      COMMAND ${LCM_GEN_EXECUTABLE} --cpp --cpp-std c++11 --cpp-hpath ${cpp_dir} ${abs}
      COMMAND ${CMAKE_COMMAND} -DHEADER=${hpp} -P ${ARPHYS_HARDEN_SCRIPT}
      DEPENDS ${abs} ${ARPHYS_HARDEN_SCRIPT}
      COMMENT "lcm-gen (C++) ${type_name}"
      VERBATIM)
    list(APPEND headers ${hpp})
    add_custom_command(
      OUTPUT ${java}
      COMMAND ${LCM_GEN_EXECUTABLE} --java --jpath ${java_dir} ${abs}
      DEPENDS ${abs}
      COMMENT "lcm-gen (Java) ${type_name}"
      VERBATIM)
    list(APPEND java_sources ${java})
  endforeach()

  add_custom_target(${target}_cpp DEPENDS ${headers})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_cpp)
  target_include_directories(${target} SYSTEM INTERFACE ${cpp_dir})
  target_link_libraries(${target} INTERFACE PkgConfig::LCM)

  if(ARG_JAR AND ARPHYS_BUILD_LCM_JAVA)
    find_package(Java COMPONENTS Development QUIET)
    find_file(LCM_JAVA_JAR lcm.jar PATHS /usr/share/java /usr/local/share/java)
    if(Java_FOUND AND LCM_JAVA_JAR)
      set(classes_dir ${CMAKE_CURRENT_BINARY_DIR}/lcmgen/classes)
      set(jar_path ${CMAKE_BINARY_DIR}/${ARG_JAR}.jar)
      add_custom_command(
        OUTPUT ${jar_path}
        COMMAND ${CMAKE_COMMAND} -E rm -rf ${classes_dir}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${classes_dir}
        COMMAND ${Java_JAVAC_EXECUTABLE} -nowarn -cp ${LCM_JAVA_JAR} -d ${classes_dir} ${java_sources}
        COMMAND ${Java_JAR_EXECUTABLE} cf ${jar_path} -C ${classes_dir} .
        DEPENDS ${java_sources}
        COMMENT "javac + jar ${ARG_JAR}.jar (message types for lcm-spy)"
        VERBATIM)
      add_custom_target(${target}_jar ALL DEPENDS ${jar_path})
      set_property(GLOBAL PROPERTY ARPHYS_LCM_JAR ${jar_path})
    else()
      message(WARNING "Java (javac) or /usr/share/java/lcm.jar not found: the lcm-spy jar is not built "
                      "(install default-jdk-headless liblcm-java, or -DARPHYS_BUILD_LCM_JAVA=OFF)")
    endif()
  endif()
endfunction()
