# VTK: the time series (STRATA_WITH_VTK) and, on top of them, headless pictures and plots
# (STRATA_WITH_RENDER, which CMakeLists.txt turns off whenever STRATA_WITH_VTK is off).
set(STRATA_HAVE_VTK 0)
set(STRATA_HAVE_RENDER 0)
set(_vtk_components "")
if(STRATA_WITH_VTK)
  set(_vtk_components CommonCore CommonDataModel IOXML IOLegacy)
  if(STRATA_WITH_RENDER)
    list(APPEND _vtk_components RenderingCore RenderingOpenGL2 RenderingAnnotation RenderingContext2D
         RenderingContextOpenGL2 RenderingFreeType InteractionStyle ChartsCore ViewsContext2D IOImage IOMovie IOOggTheora
         FiltersSources FiltersCore FiltersGeneral)
  endif()
  find_package(VTK 9.1 REQUIRED COMPONENTS ${_vtk_components})
  set(STRATA_HAVE_VTK 1)
  if(STRATA_WITH_RENDER)
    # ensure_display() opens a test connection to $DISPLAY with Xlib (VTK links it anyway).
    find_package(X11 REQUIRED)
    set(STRATA_HAVE_RENDER 1)
  endif()
endif()
