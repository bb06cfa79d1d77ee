"""File formats: readers and writers by format (tables, BVH, ASF/AMC, C3D, JSON, glTF, USD); every writer atomic."""
