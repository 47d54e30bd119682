# Adds every immediate sub-folder of DIR that holds a CMakeLists.txt,
# in sorted order, so that components can be added without editing a list.
# -DEVADE_COMPONENTS="bus;config;..." limits the build to folders of those
# names (handy while one component is being worked on); empty = all.
set(EVADE_COMPONENTS "" CACHE STRING "only build folders with these names (empty: all)")
function(evade_add_subdirs dir)
  file(GLOB children RELATIVE ${CMAKE_CURRENT_SOURCE_DIR}/${dir}
       ${CMAKE_CURRENT_SOURCE_DIR}/${dir}/*/CMakeLists.txt)
  list(SORT children)
  foreach(child ${children})
    get_filename_component(sub ${child} DIRECTORY)
    if(EVADE_COMPONENTS AND NOT sub IN_LIST EVADE_COMPONENTS)
      continue()
    endif()
    add_subdirectory(${dir}/${sub})
  endforeach()
  if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${dir}/CMakeLists.txt)
    add_subdirectory(${dir})
  endif()
endfunction()
