// gmsh: being written
