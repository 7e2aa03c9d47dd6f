// [output]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into OutputTable.
#include "table_file.hpp"

namespace strata::scene::tables {

TableSpec output_spec() {
  return {
      "output",
      false,
      false,
      "What a run writes, and how often.",
      {
          K("directory", OutputPath)
              .def(R"("out")")
              .doc("Output folder, relative to the scene file; `strata run -o` overrides it."),
          K("frames", Integer)
              .ge(0)
              .def("20")
              .doc("Number of VTK frames, evenly spaced over the run; 0 writes none. "
                   "frame_every_breaks and frame_every_time take precedence."),
          K("frame_every_time", Real, "s")
              .ge(0)
              .def("0.0")
              .doc("Simulated time between two frames (at the nearest step), plus the first and the "
                   "last; 0: not used. Takes precedence over frames."),
          K("frame_every_breaks", Integer)
              .ge(0)
              .def("0")
              .doc("Write a frame whenever this many more bonds have broken since the last frame "
                   "(checked at every probe row), plus the first and the last; 0: not used. Takes "
                   "precedence over frame_every_time and frames."),
          K("checkpoint_every", Integer, "steps")
              .ge(0)
              .def("0")
              .doc("Steps between two checkpoints (`checkpoint.h5` in the output folder, replaced "
                   "each time); 0: only at the end of the run and when it is interrupted (SIGINT, "
                   "SIGTERM). `strata run SCENE --restart checkpoint.h5` continues the run. Needs "
                   "STRATA_WITH_HDF5."),
          K("probe_every", Integer, "steps")
              .ge(0)
              .def("0")
              .doc("Steps between two probe rows; 0 gives about 1000 rows per run."),
          K("vtk", Bool)
              .def("true")
              .doc("Write VTK frames (.vtp/.vtu files and a .pvd collection) for ParaView."),
          K("render", Bool).def("true").doc("Render the frames to PNG pictures."),
          K("render_field", Choice)
              .choices({"displacement", "velocity", "damage", "group", "shear_strain"})
              .def(R"("damage")")
              .doc("What colours the particles in the pictures; damage also colours broken bonds "
                   "by how they broke (tension or shear); group colours each particle by its last "
                   "group (e.g. its layer); shear_strain (2D) shows shear zones such as faults."),
          K("fields", StringList)
              .choices(
                  {"id", "radius", "displacement", "velocity", "force", "group", "damage", "shear_strain"})
              .def(R"(["id", "radius", "displacement", "velocity", "force", "group", "damage"])")
              .doc("Per-particle fields written to the VTK frames (the render field is always written). "
                   "shear_strain (2D): the maximum shear strain ln(λ1/λ2) of the deformation since the "
                   "start (after settling) of each particle's neighbourhood (the particles within 1.5 "
                   "diameters of it at the start), which traces faults and shear bands where bonds have "
                   "broken or never were."),
          K("movie", Bool)
              .def("true")
              .doc("Join the pictures into a movie: movie.mp4 (H.264) when ffmpeg is installed, otherwise "
                   "movie.ogv (Ogg Theora, written by VTK)."),
          K("render_while_running", Bool)
              .def("false")
              .doc("Render each frame to PNG as soon as it is written, so pictures of a long run can be "
                   "watched while it goes on (each picture then has its own colour range, except for "
                   "damage); otherwise all frames are rendered at the end with one colour range."),
          K("render_contacts", Bool)
              .def("false")
              .doc("Also draw the contacts of the bond frames (output.contacts) in the pictures, as thin "
                   "green lines."),
          K("render_cracks", Bool)
              .def("true")
              .doc("Draw the broken bonds over the particles in the pictures; false leaves the particles "
                   "alone (e.g. a sandbox's layers coloured by group, whose offsets show the faults)."),
          K("render_size", IntegerList)
              .ge(16)
              .length(2, 2)
              .def("[1600, 1200]")
              .doc("Width and height of the pictures in pixels (a long, thin model reads better wide)."),
          K("view_direction", RealList)
              .length(3, 3)
              .def("[-1.0, -0.6, -0.45]")
              .doc("3D pictures: direction from the camera towards the model (need not be a unit vector; "
                   "not zero). 2D pictures always look down -z."),
          K("view_up", RealList)
              .length(3, 3)
              .def("[0.0, 0.0, 1.0]")
              .doc("3D pictures: the direction that points up in the picture (not zero, not parallel to "
                   "view_direction)."),
          K("clip_plane", RealList)
              .length(6, 6)
              .doc("3D pictures: a clip plane [ox, oy, oz, nx, ny, nz], a point (m) and a normal (not "
                   "zero); particles, cracks and FEM cells on the normal's side are left out, so the "
                   "inside shows. Not set: nothing is clipped."),
          K("particles", Choice)
              .choices({"all", "surface", "surface_and_slice", "none"})
              .def(R"("all")")
              .doc("Which particles the VTK frames hold: all; surface (the particles that had fewer "
                   "bonds at the start than one inside the lattice: the skin of every region and of its "
                   "holes); surface_and_slice (the surface and, besides, every particle of the slice, "
                   "which slice_thickness must then give: the outside of a large model and a cut "
                   "through it; bonds and contacts those of the slice); none. Large models can write "
                   "only what a workstation can open."),
          K("groups", StringList)
              .def("[]")
              .doc("Only particles of these [[group]]s or [[region]]s in the VTK frames, and only the bonds "
                   "and contacts between two of them; empty: all."),
          K("slice_point", RealList, "m")
              .per_axis()
              .def("[0.0, 0.0, 0.0]")
              .doc("A point of the slice plane (see slice_thickness)."),
          K("slice_normal", RealList)
              .per_axis()
              .def("[0.0, 0.0, 1.0]")
              .doc("Normal of the slice plane (see slice_thickness)."),
          K("slice_thickness", Real, "m")
              .ge(0)
              .def("0.0")
              .doc("Only particles whose centres lie within half this distance of the slice plane "
                   "(slice_point, slice_normal) in the VTK frames, and the bonds and contacts between two of "
                   "them (with particles = \"surface_and_slice\": these and the surface); 0: no slice."),
          K("bonds", Choice)
              .choices({"broken", "all", "none"})
              .def(R"("broken")")
              .doc(
                  "Which bonds the bond frames hold: broken (cracks, each as it is at the frame's time: open "
                  "in tension or shear, or closed while it touches again), all (also intact bonds, with "
                  "their "
                  "forces), none."),
          K("contacts", Bool)
              .def("true")
              .doc("Also write the contacts between particles that were never bonded and touch now to the "
                   "bond frames, as lines with state 4, Fn and Fs; only those whose two particles pass "
                   "output.groups and the slice. Pictures draw them only with render_contacts."),
      }};
}

OutputTable read_output(const Table& t) {
  Reader read(t, "output");
  OutputTable o;
  o.pos = t.where();
  read("directory", o.directory);
  read("frames", o.frames);
  read("frame_every_time", o.frame_every_time);
  read("frame_every_breaks", o.frame_every_breaks);
  read("checkpoint_every", o.checkpoint_every);
  read("probe_every", o.probe_every);
  read("vtk", o.vtk);
  read("render", o.render);
  read("render_field", o.render_field);
  read("fields", o.fields);
  read("movie", o.movie);
  read("render_while_running", o.render_while_running);
  read("render_contacts", o.render_contacts);
  read("render_cracks", o.render_cracks);
  read("render_size", o.render_size);
  read("view_direction", o.view_direction);
  read("view_up", o.view_up);
  read("clip_plane", o.clip_plane);
  read("particles", o.particles);
  read("groups", o.groups);
  read("slice_point", o.slice_point);
  read("slice_normal", o.slice_normal);
  read("slice_thickness", o.slice_thickness);
  read("bonds", o.bonds);
  read("contacts", o.contacts);
  read.done();
  return o;
}

}  // namespace strata::scene::tables
