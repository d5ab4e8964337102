#!/usr/bin/env python3
"""Writes the malformed data files of the bad-input corpus into data/ (committed; rerun after
changing this script). Usage: tests/app/bad_input/make_data.py   (needs mpicc and libhdf5-openmpi-dev
for the one HDF5 file)."""
import os
import struct
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data")

TETRA_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TETRA_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def write(name, content):
    path = os.path.join(DATA, name)
    mode = "wb" if isinstance(content, bytes) else "w"
    with open(path, mode) as f:
        f.write(content)


def ply_ascii(vertex_count=4, face_count=4, vertices=TETRA_V, faces=TETRA_F, end=True,
              header_extra="", fmt="ascii 1.0", vertex_props=("x", "y", "z")):
    head = ["ply", "format " + fmt, "element vertex %d" % vertex_count]
    head += ["property float %s" % p for p in vertex_props]
    head += ["element face %d" % face_count, "property list uchar int vertex_indices"]
    if header_extra:
        head.append(header_extra)
    if end:
        head.append("end_header")
    body = ["%s %s %s" % v for v in vertices] + ["3 %d %d %d" % f for f in faces]
    return "\n".join(head + body) + "\n"


def ply_binary(vertex_count=4, face_count=4, vertices=TETRA_V, faces=TETRA_F, cut=0):
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
            "property float y\nproperty float z\nelement face %d\n"
            "property list uchar int vertex_indices\nend_header\n" % (vertex_count, face_count))
    body = b"".join(struct.pack("<3f", *v) for v in vertices)
    body += b"".join(struct.pack("<B3i", 3, *f) for f in faces)
    data = head.encode() + body
    return data[: len(data) - cut] if cut else data


def stl_binary(count, triangles):
    data = b"binary stl made for texsim's bad-input corpus".ljust(80, b"\0")
    data += struct.pack("<I", count)
    for tri in triangles:
        data += struct.pack("<3f", 0, 0, 1)
        for v in tri:
            data += struct.pack("<3f", *v)
        data += b"\0\0"
    return data


def stl_ascii(coordinate="0"):
    return ("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
            "vertex %s 1 0\nendloop\nendfacet\nendsolid t\n" % coordinate)


def obj(vertices=TETRA_V, faces=TETRA_F, extra=""):
    lines = ["v %s %s %s" % v for v in vertices]
    lines += ["f %d %d %d" % tuple(i + 1 for i in f) for f in faces]
    return "\n".join(lines) + "\n" + extra


def off(header="OFF\n4 4 6\n", vertices=TETRA_V, faces=TETRA_F):
    return header + "".join("%s %s %s\n" % v for v in vertices) + \
        "".join("3 %d %d %d\n" % f for f in faces)


def inr(fields, voxel_bytes):
    text = "#INRIMAGE-4#{\n" + "".join("%s=%s\n" % kv for kv in fields)
    pad = 256 - (len(text) + 4) % 256
    header = (text + "\n" * (pad % 256) + "##}\n").encode()
    return header + voxel_bytes


def vti(extent, values):
    return ('<?xml version="1.0"?>\n<VTKFile type="ImageData" version="0.1" '
            'byte_order="LittleEndian">\n<ImageData WholeExtent="%s" Origin="0 0 0" '
            'Spacing="1 1 1">\n<Piece Extent="%s">\n<PointData Scalars="density">\n'
            '<DataArray type="Float32" Name="density" format="ascii">%s</DataArray>\n'
            '</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n' % (extent, extent, values))


HDF5_SOURCE = r"""
#include <hdf5.h>
/* One float dataset of 4194304 x 2097152 x 2097152 voxels: chunked, never written, so the file
   is small while the product of its dimensions overflows 64 bits. */
int main(int argc, char** argv) {
  hsize_t dims[3] = {2097152, 2097152, 4194304}, chunk[3] = {1, 1, 16};
  hid_t file = H5Fcreate(argv[1], H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  hid_t space = H5Screate_simple(3, dims, NULL);
  hid_t plist = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(plist, 3, chunk);
  hid_t set = H5Dcreate2(file, "density", H5T_IEEE_F32LE, space, H5P_DEFAULT, plist, H5P_DEFAULT);
  H5Dclose(set); H5Pclose(plist); H5Sclose(space); H5Fclose(file);
  return 0;
}
"""


def make_hdf5(name):
    with tempfile.TemporaryDirectory() as tmp:
        source = os.path.join(tmp, "huge.c")
        with open(source, "w") as f:
            f.write(HDF5_SOURCE)
        program = os.path.join(tmp, "huge")
        subprocess.run(["mpicc", source, "-o", program, "-I/usr/include/hdf5/openmpi",
                        "-L/usr/lib/x86_64-linux-gnu/hdf5/openmpi", "-lhdf5"], check=True)
        subprocess.run([program, os.path.join(DATA, name)], check=True)


def main():
    os.makedirs(DATA, exist_ok=True)
    # PLY
    write("ply_counts_exceed_body.ply", ply_ascii(vertex_count=4000, face_count=4000))
    write("ply_no_end_header.ply", ply_ascii(end=False))
    write("ply_binary_truncated.ply", ply_binary(cut=7))
    write("ply_binary_counts_exceed_body.ply", ply_binary(vertex_count=1000000, face_count=2000000))
    write("ply_face_index_out_of_range.ply", ply_ascii(faces=TETRA_F[:3] + [(1, 2, 99)]))
    write("ply_nan_vertex.ply", ply_ascii(vertices=TETRA_V[:3] + [("nan", 0, 1)]))
    write("ply_binary_inf_vertex.ply", ply_binary(vertices=TETRA_V[:3] + [(float("inf"), 0, 1)]))
    write("ply_unknown_format.ply", ply_ascii(fmt="binary_middle_endian 1.0"))
    write("ply_unknown_property_type.ply", ply_ascii(header_extra="property float128 w"))
    write("ply_negative_count.ply", ply_ascii(vertex_count=-4))
    write("ply_huge_count.ply", ply_ascii(vertex_count=99999999999))
    write("ply_no_z.ply", ply_ascii(vertex_props=("x", "y")))
    write("ply_not_a_number.ply", ply_ascii(vertices=TETRA_V[:3] + [("zero", 0, 1)]))
    write("ply_missing_magic.ply", "format ascii 1.0\nelement vertex 0\nend_header\n")
    write("ply_empty.ply", "")
    # Files on which VTK 9.1's readers crash (found by fuzz/): refused before VTK sees them.
    write("ply_face_before_vertex.ply",
          "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
          "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
          "3 0 1 2\n0 0 0\n1 0 0\n0 1 0\n")
    write("ply_element_without_properties.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
          "property float z\nelement extra 1\nend_header\n0 0 0\n1 0 0\n0 1 0\n1\n")
    write("ply_vertex_list_property.ply",
          ply_ascii(vertex_props=("x", "y", "z"), header_extra="").replace(
              "property float z\n", "property float z\nproperty list uchar int extra\n", 1)
          .replace("0 0 0\n", "0 0 0 0\n").replace("1 0 0\n", "1 0 0 0\n")
          .replace("0 1 0\n", "0 1 0 0\n").replace("0 0 1\n", "0 0 1 0\n"))
    write("ply_nul_in_header.ply", ply_ascii().replace("element face", "\0\0\1face", 1))
    write("ply_duplicate_property.ply", ply_ascii(vertex_props=("x", "y", "x")))
    write("ply_empty_body_line.ply", ply_ascii().replace("end_header\n", "end_header\n\n"))
    write("ply_form_feed_in_body.ply", ply_ascii().replace("\n1 0 0\n", "\n1 0\f0\n", 1))
    write("ply_long_line.ply", ply_ascii().replace("\n1 0 0\n", "\n1 0 0" + " " * 5000 + "\n", 1))
    # STL
    write("stl_count_exceeds_data.stl", stl_binary(1000, [TETRA_V[:3]]))
    write("stl_short_header.stl", b"\x00\x01\x02" * 10)
    write("stl_ascii_nan.stl", stl_ascii("nan"))
    write("stl_ascii_inf.stl", stl_ascii("-inf"))
    write("stl_empty.stl", "")
    write("stl_ascii_outside_grammar.stl", stl_ascii().replace("outer loop", "outer lop"))
    # Text in STL's ASCII grammar whose vertical tabs (binary to VTK, white space to isspace) make
    # 6 % of its bytes: VTK reads it as binary, with bytes 80-83 ("abcd") as 1.7e9 triangles.
    write("stl_vertical_tabs_binary.stl",
          (b"solid t" + b"\v" * 6 + b"\nendsolid " + b"t" * 57 + b"abcd").ljust(100, b"t"))
    # OBJ
    write("obj_nan_vertex.obj", obj(vertices=TETRA_V[:3] + [("nan", "0", "1")]))
    write("obj_inf_vertex.obj", obj(vertices=TETRA_V[:3] + [("0", "inf", "1")]))
    write("obj_face_index_out_of_range.obj", obj(extra="f 1 2 9\n"))
    write("obj_face_index_zero.obj", obj(extra="f 0 1 2\n"))
    write("obj_short_vertex.obj", obj(extra="v 1 2\n"))
    write("obj_no_faces.obj", obj(faces=[]))
    write("obj_mixed_corner_forms.obj", obj(extra="vn 0 0 1\nf 1//1 2/ 3\n"))
    write("obj_texture_index_out_of_range.obj", obj(extra="vt 0 0\nf 1/1 2/5 3/1\n"))
    # OFF
    write("off_nan_vertex.off", off(vertices=TETRA_V[:3] + [("nan", 0, 1)]))
    write("off_inf_vertex.off", off(vertices=TETRA_V[:3] + [(0, "1e999", 1)]))
    write("off_counts_exceed_file.off", off(header="OFF\n40000 40000 0\n"))
    write("off_bad_keyword.off", off(header="NOFF\n4 4 6\n"))
    write("off_truncated.off", off()[:-9])
    write("off_face_index_out_of_range.off", off(faces=TETRA_F[:3] + [(1, 2, 7)]))
    write("off_two_vertex_face.off", off(header="OFF\n4 1 0\n", faces=[]) + "2 0 1\n")
    write("off_degenerate.off", off(vertices=[(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)]))
    write("off_nonmanifold.off", off(header="OFF\n5 3 0\n",
                                     vertices=TETRA_V + [(0, -1, 0)],
                                     faces=[(0, 1, 2), (0, 1, 3), (0, 1, 4)]))
    # INR
    float_header = [("XDIM", 4), ("YDIM", 4), ("ZDIM", 4), ("VDIM", 1), ("TYPE", "float"),
                    ("PIXSIZE", "32 bits"), ("CPU", "decm")]
    write("inr_overflow.inr", inr([("XDIM", 4194304), ("YDIM", 2097152), ("ZDIM", 2097152),
                                   ("VDIM", 1), ("TYPE", "unsigned fixed"),
                                   ("PIXSIZE", "8 bits"), ("CPU", "decm")], b"\0" * 64))
    write("inr_huge.inr", inr([("XDIM", 65536), ("YDIM", 65536), ("ZDIM", 65536), ("VDIM", 1),
                               ("TYPE", "unsigned fixed"), ("PIXSIZE", "8 bits"),
                               ("CPU", "decm")], b"\0" * 64))
    write("inr_truncated.inr", inr(float_header, b"\0" * 100))
    write("inr_nan_voxel.inr", inr(float_header,
                                   struct.pack("<64f", *([0.5] * 20 + [float("nan")] + [0.5] * 43))))
    write("inr_no_end.inr", "#INRIMAGE-4#{\nXDIM=4\n")
    write("inr_bad_type.inr", inr([("XDIM", 4), ("YDIM", 4), ("ZDIM", 4), ("TYPE", "complex"),
                                   ("PIXSIZE", "32 bits")], b"\0" * 256))
    write("inr_negative_dim.inr", inr([("XDIM", -4), ("YDIM", 4), ("ZDIM", 4),
                                       ("TYPE", "float"), ("PIXSIZE", "32 bits")], b"\0" * 256))
    # VTK image data
    write("vti_huge_extent.vti", vti("0 2000000 0 2000000 0 2000000", "0 1 2 3"))
    write("vti_nan_voxel.vti", vti("0 1 0 1 0 1", "0 1 nan 3 4 5 6 7"))
    write("vti_not_xml.vti", "this is not an image\n")
    # HDF5
    make_hdf5("hdf5_overflow.h5")
    write("hdf5_not_hdf5.h5", "plain text, not HDF5\n")
    # A well-formed mesh for cases whose fault is elsewhere.
    write("tetrahedron.off", off())


if __name__ == "__main__":
    main()
