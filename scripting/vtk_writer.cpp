// SPDX-License-Identifier: MIT
// VTK XML writer for ParaView (vtk_writer.hpp). File format: VTK's "VTK File Formats" document,
// XML section: a PolyData piece whose DataArrays all have format="appended" and an offset into
// the <AppendedData encoding="raw"> block that follows "_"; each array there is a UInt64 byte
// count followed by the raw values.
#include "vtk_writer.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "talus/errors.hpp"

namespace talus::vtk {

namespace {

bool littleEndian() {
    const uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    return first == 1;
}

/// One DataArray: its XML attributes and its raw bytes.
struct Array {
    std::string name, type;
    int components = 1;
    std::string bytes;
};

template <class T>
void append(std::string& out, T v) {
    char buf[sizeof(T)];
    std::memcpy(buf, &v, sizeof(T));
    out.append(buf, sizeof(T));
}

Array f64(const std::string& name, const std::vector<double>& v, int components = 1) {
    Array a{name, "Float64", components, {}};
    a.bytes.reserve(v.size() * 8);
    for (double x : v) append(a.bytes, x);
    return a;
}

Array i64(const std::string& name, const std::vector<int64_t>& v) {
    Array a{name, "Int64", 1, {}};
    for (int64_t x : v) append(a.bytes, x);
    return a;
}

Array u8(const std::string& name, const std::vector<uint8_t>& v) {
    Array a{name, "UInt8", 1, {}};
    a.bytes.assign(v.begin(), v.end());
    return a;
}

/// A vtkStringArray in binary form: the strings one after another, each ended by a zero byte.
Array strings(const std::string& name, const std::vector<std::string>& v) {
    Array a{name, "String", 1, {}};
    for (const std::string& s : v) {
        a.bytes += s;
        a.bytes += '\0';
    }
    return a;
}

/// 2D vectors as VTK's 3-component vectors (z = 0), so ParaView treats them as vectors.
void push3(std::vector<double>& out, const Vec2& v) {
    out.push_back(v.x());
    out.push_back(v.y());
    out.push_back(0.0);
}

std::string xmlEscape(const std::string& s) {
    std::string out;
    for (char c : s) switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    return out;
}

std::string exact(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

/// A PolyData file of points with either vertex cells (one per point) or line cells.
struct PolyData {
    std::vector<double> points;  // x, y, z
    std::vector<int64_t> connectivity, offsets;
    bool lines = false;  // cells are lines (else vertices)
    std::vector<Array> point_data, cell_data;
    std::vector<Array> field_data;

    std::size_t pointCount() const { return points.size() / 3; }

    void write(const std::string& path) const {
        std::string xml, blob;
        const auto add = [&](const Array& a, const char* indent) {
            std::ostringstream s;
            s << indent << "<DataArray type=\"" << a.type << "\" Name=\"" << xmlEscape(a.name)
              << "\"";
            if (a.type == "String" || a.components != 1)
                s << " NumberOfComponents=\"" << a.components << "\"";
            if (a.type == "String") {
                // A string array has no fixed size per value: the reader needs the count.
                std::size_t n = 0;
                for (char c : a.bytes) n += c == '\0';
                s << " NumberOfTuples=\"" << n << "\"";
            }
            s << " format=\"appended\" offset=\"" << blob.size() << "\"/>\n";
            xml += s.str();
            append(blob, static_cast<uint64_t>(a.bytes.size()));
            blob += a.bytes;
        };
        const std::size_t cells = offsets.size();
        std::ostringstream head;
        head << "<?xml version=\"1.0\"?>\n"
             << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\""
             << (littleEndian() ? "LittleEndian" : "BigEndian") << "\" header_type=\"UInt64\">\n"
             << "  <PolyData>\n";
        xml += head.str();
        if (!field_data.empty()) {
            xml += "    <FieldData>\n";
            for (const Array& a : field_data) {
                // Field data needs its tuple count on the element.
                std::size_t n = a.type == "String" ? 0 : a.bytes.size() / 8;
                if (a.type == "String")
                    for (char c : a.bytes) n += c == '\0';
                std::ostringstream s;
                s << "      <DataArray type=\"" << a.type << "\" Name=\"" << xmlEscape(a.name)
                  << "\" NumberOfTuples=\"" << n << "\" format=\"appended\" offset=\""
                  << blob.size() << "\"/>\n";
                xml += s.str();
                append(blob, static_cast<uint64_t>(a.bytes.size()));
                blob += a.bytes;
            }
            xml += "    </FieldData>\n";
        }
        std::ostringstream piece;
        piece << "    <Piece NumberOfPoints=\"" << pointCount() << "\" NumberOfVerts=\""
              << (lines ? 0 : cells) << "\" NumberOfLines=\"" << (lines ? cells : 0)
              << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
        xml += piece.str();
        xml += "      <PointData>\n";
        for (const Array& a : point_data) add(a, "        ");
        xml += "      </PointData>\n      <CellData>\n";
        for (const Array& a : cell_data) add(a, "        ");
        xml += "      </CellData>\n      <Points>\n";
        add(f64("Points", points, 3), "        ");
        xml += "      </Points>\n";
        xml += lines ? "      <Lines>\n" : "      <Verts>\n";
        add(i64("connectivity", connectivity), "        ");
        add(i64("offsets", offsets), "        ");
        xml += lines ? "      </Lines>\n" : "      </Verts>\n";
        xml += "    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
        std::ofstream f(path, std::ios::binary | std::ios::trunc);
        f << xml;
        f.write(blob.data(), static_cast<std::streamsize>(blob.size()));
        f << "\n  </AppendedData>\n</VTKFile>\n";
        f.close();
        if (!f) throw Error("vtk: cannot write '" + path + "' (" + std::strerror(errno) + ")");
    }
};

void writeTextAtomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::trunc);
        f << text;
        f.close();
        if (!f) throw Error("vtk: cannot write '" + tmp + "' (" + std::strerror(errno) + ")");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
        throw Error("vtk: cannot rename '" + tmp + "' to '" + path + "' (" + std::strerror(errno) +
                    ")");
}

std::string frameStem(const SeriesState& s, int64_t frame) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "_%06lld", static_cast<long long>(frame));
    return s.name + buf;
}

/// Per-group 0/1 arrays ("group_rock"): ParaView thresholds on them; names in the model's
/// group order.
void addGroupArrays(std::vector<Array>& out, const std::vector<std::string>& all,
                    const std::vector<std::vector<std::string>>& per_item) {
    for (const std::string& g : all) {
        std::vector<uint8_t> in(per_item.size(), 0);
        bool any = false;
        for (std::size_t i = 0; i < per_item.size(); ++i)
            for (const std::string& h : per_item[i])
                if (h == g) in[i] = 1, any = true;
        if (any) out.push_back(u8("group_" + g, in));
    }
}

/// A line cell from a to b (walls, contacts and cracks are line parts).
void addSegment(PolyData& p, const Vec2& a, const Vec2& b) {
    const auto first = static_cast<int64_t>(p.pointCount());
    push3(p.points, a);
    push3(p.points, b);
    p.connectivity.push_back(first);
    p.connectivity.push_back(first + 1);
    p.offsets.push_back(first + 2);
}

/// The optional built-in ball array `f` (optionalBallFields) over `ids`.
Array optionalBallArray(const Model& m, const std::vector<BallId>& ids, const std::string& f) {
    std::vector<double> v;
    int comps = 1;
    for (const BallId b : ids) {
        if (f == "force") {
            push3(v, m.ballForce(b)), comps = 3;
        } else if (f == "applied_force") {
            push3(v, m.ballAppliedForce(b)), comps = 3;
        } else if (f == "moment") {
            v.push_back(m.ballMoment(b));
        } else if (f == "mass") {
            v.push_back(m.ballMass(b));
        } else if (f == "density") {
            v.push_back(m.ballDensity(b));
        } else if (f == "angle") {
            v.push_back(m.ballAngle(b));
        } else if (f == "speed") {
            v.push_back(m.ballVel(b).norm());
        } else if (f == "fixity") {
            v.push_back(m.ballFixity(b));
        } else {
            throw Error("vtk: unknown ball field '" + f + "'");
        }
    }
    return f64(f, v, comps);
}

/// Balls: one vertex per particle, with its arrays, the optional built-in ones (`fields`) and
/// the caller's (`extra`).
PolyData ballsPart(const Model& m, const std::vector<std::string>& fields,
                   const std::vector<BallArray>& extra, const std::vector<Array>& field_data) {
    PolyData p;
    p.field_data = field_data;
    const std::vector<BallId> ids = particleIds(m);
    const std::size_t n = ids.size();
    std::vector<double> radius, vel, spin;
    std::vector<int64_t> id, clump;
    std::vector<std::vector<std::string>> ball_groups;
    radius.reserve(n), spin.reserve(n), vel.reserve(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const BallId b = ids[i];
        push3(p.points, m.ballPos(b));
        p.connectivity.push_back(static_cast<int64_t>(i));
        p.offsets.push_back(static_cast<int64_t>(i + 1));
        id.push_back(b.index);
        radius.push_back(m.ballRadius(b));
        push3(vel, m.ballVel(b));
        spin.push_back(m.ballSpin(b));
        clump.push_back(m.clumpOf(b).index);  // 0: a free ball
        ball_groups.push_back(m.ballGroups(b));
    }
    p.point_data = {i64("id", id), f64("radius", radius), f64("velocity", vel, 3),
                    f64("spin", spin), i64("clump", clump)};
    addGroupArrays(p.point_data, m.groupNames(), ball_groups);
    for (const std::string& f : fields) p.point_data.push_back(optionalBallArray(m, ids, f));
    for (const BallArray& a : extra) {
        if (a.values.size() != static_cast<std::size_t>(a.components) * n)
            throw Error("vtk: field '" + a.name + "' has " + std::to_string(a.values.size()) +
                        " values for " + std::to_string(n) + " balls");
        p.point_data.push_back(f64(a.name, a.values, a.components));
    }
    return p;
}

/// Walls: one polyline per wall chain.
PolyData wallsPart(const Model& m, const std::vector<Array>& field_data) {
    PolyData p;
    p.lines = true;
    p.field_data = field_data;
    std::vector<int64_t> id;
    std::vector<double> vel, spin, force;
    std::vector<std::vector<std::string>> wall_groups;
    for (const WallId w : m.wallIds()) {
        const std::vector<Vec2> pts = m.wallPoints(w);
        const auto first = static_cast<int64_t>(p.pointCount());
        for (const Vec2& q : pts) push3(p.points, q);
        for (std::size_t k = 0; k < pts.size(); ++k)
            p.connectivity.push_back(first + static_cast<int64_t>(k));
        // A closed wall repeats its first point (wallPoints lists each vertex once).
        if (m.wallClosed(w)) p.connectivity.push_back(first);
        p.offsets.push_back(static_cast<int64_t>(p.connectivity.size()));
        id.push_back(w.index);
        push3(vel, m.wallVel(w));
        spin.push_back(m.wallSpin(w));
        push3(force, m.wallForce(w));
        wall_groups.push_back(m.wallGroups(w));
    }
    p.cell_data = {i64("id", id), f64("velocity", vel, 3), f64("spin", spin),
                   f64("force", force, 3)};
    addGroupArrays(p.cell_data, m.groupNames(), wall_groups);
    return p;
}

/// Contacts: a line from end 1's centre to end 2's centre (to the contact point for a wall), so
/// a ball-ball line crosses the contact point.
PolyData contactsPart(const Model& m, const std::vector<Array>& field_data) {
    PolyData p;
    p.lines = true;
    p.field_data = field_data;
    std::vector<double> fn, fs, mom, overlap, normal;
    std::vector<int64_t> end1, end2, model_index;
    std::vector<uint8_t> wall, bonded, sliding;
    std::vector<std::string> model;
    std::map<std::string, int64_t> model_ids;
    for (const ContactInfo& c : m.contacts(true)) {
        addSegment(p, m.ballPos(c.ball1), c.wall.valid() ? c.point : m.ballPos(c.ball2));
        fn.push_back(c.normal_force);
        fs.push_back(c.shear_force);
        mom.push_back(c.moment);
        overlap.push_back(c.overlap);
        push3(normal, c.normal);
        end1.push_back(c.ball1.index);
        end2.push_back(c.wall.valid() ? c.wall.index : c.ball2.index);
        wall.push_back(c.wall.valid() ? 1 : 0);
        bonded.push_back(c.bonded ? 1 : 0);
        sliding.push_back(c.sliding ? 1 : 0);
        model.push_back(c.model);
        model_ids.emplace(c.model, 0);
    }
    // Model names as numbers too (ParaView colours by numbers, not strings): the index in the
    // sorted list "model_names" of the field data.
    std::vector<std::string> names;
    for (auto& [name, index] : model_ids) {
        index = static_cast<int64_t>(names.size());
        names.push_back(name);
    }
    for (const std::string& s : model) model_index.push_back(model_ids[s]);
    p.cell_data = {f64("normal_force", fn),
                   f64("shear_force", fs),
                   f64("moment", mom),
                   f64("overlap", overlap),
                   f64("normal", normal, 3),
                   i64("end1", end1),
                   i64("end2", end2),
                   u8("wall", wall),
                   u8("bonded", bonded),
                   u8("sliding", sliding),
                   i64("model_index", model_index),
                   strings("model", model)};
    if (!names.empty()) p.field_data.push_back(strings("model_names", names));
    return p;
}

/// Cracks: a line across each broken bond (crack.hpp), through the contact point where it
/// broke, 2 x the bond's radius long; mode 1 tension, 2 shear.
PolyData cracksPart(const std::vector<Crack>& cracks, const std::vector<Array>& field_data) {
    PolyData p;
    p.lines = true;
    p.field_data = field_data;
    std::vector<double> time, width, normal;
    std::vector<int64_t> mode, step, end1, end2;
    for (const Crack& c : cracks) {
        addSegment(p, c.end1(), c.end2());
        mode.push_back(c.mode);
        time.push_back(c.time);
        step.push_back(c.step);
        width.push_back(2.0 * c.radius);
        push3(normal, c.normal);
        end1.push_back(c.ball1.index);
        end2.push_back(c.ball2.index);
    }
    p.cell_data = {i64("mode", mode),   f64("time", time),        i64("step", step),
                   f64("width", width), f64("normal", normal, 3), i64("ball1", end1),
                   i64("ball2", end2)};
    return p;
}

/// The frame's multiblock file: its parts, by name.
std::string multiblockText(const SeriesState& st, const std::string& stem) {
    std::ostringstream s;
    s << "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" "
         "byte_order=\""
      << (littleEndian() ? "LittleEndian" : "BigEndian")
      << "\" header_type=\"UInt64\">\n  <vtkMultiBlockDataSet>\n";
    int index = 0;
    const auto part = [&](bool on, const char* name) {
        if (on)
            s << "    <DataSet index=\"" << index++ << "\" name=\"" << name << "\" file=\""
              << xmlEscape(stem) << "_" << name << ".vtp\"/>\n";
    };
    part(true, "balls");
    part(st.walls, "walls");
    part(st.contacts, "contacts");
    part(st.cracks, "cracks");
    s << "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
    return s.str();
}

}  // namespace

std::vector<BallId> particleIds(const Model& m) {
    std::vector<BallId> ids = m.ballIds();
    for (const ClumpId c : m.clumpIds())
        for (const BallId b : m.clumpPebbleIds(c)) ids.push_back(b);
    return ids;
}

const std::vector<std::string>& optionalBallFields() {
    static const std::vector<std::string> names = {"force", "moment", "mass",          "density",
                                                   "angle", "speed",  "applied_force", "fixity"};
    return names;
}

Series::Series(SeriesState state) : m_state(std::move(state)) {
    if (m_state.dir.empty()) m_state.dir = ".";
    struct stat st {};
    if (::stat(m_state.dir.c_str(), &st) != 0) {
        if (::mkdir(m_state.dir.c_str(), 0777) != 0)
            throw Error("vtk: cannot create directory '" + m_state.dir + "' (" +
                        std::strerror(errno) + ")");
    } else if (!S_ISDIR(st.st_mode)) {
        throw Error("vtk: '" + m_state.dir + "' exists and is not a directory");
    }
}

std::string Series::pvdPath() const { return m_state.dir + "/" + m_state.name + ".pvd"; }

void Series::writeFrame(const Model& m, const std::vector<BallArray>& extra,
                        const std::vector<Crack>& cracks) {
    const int64_t frame = m_state.next_frame;
    const std::string stem = frameStem(m_state, frame);
    const std::string base = m_state.dir + "/" + stem;
    const std::vector<Array> field{f64("TimeValue", {m.time()}),
                                   i64("step", {static_cast<int64_t>(m.step())})};
    ballsPart(m, m_state.fields, extra, field).write(base + "_balls.vtp");
    if (m_state.walls) wallsPart(m, field).write(base + "_walls.vtp");
    if (m_state.contacts) contactsPart(m, field).write(base + "_contacts.vtp");
    if (m_state.cracks) cracksPart(cracks, field).write(base + "_cracks.vtp");
    writeTextAtomically(base + ".vtm", multiblockText(m_state, stem));
    m_state.frames.push_back(FrameEntry{frame, m.step(), m.time(), stem + ".vtm"});
    m_state.next_frame = frame + 1;
    writePvd();
}

void Series::writePvd() const {
    std::ostringstream s;
    s << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\""
      << (littleEndian() ? "LittleEndian" : "BigEndian")
      << "\" header_type=\"UInt64\">\n  <Collection>\n";
    for (const FrameEntry& f : m_state.frames)
        s << "    <DataSet timestep=\"" << exact(f.time) << "\" group=\"\" part=\"0\" file=\""
          << xmlEscape(f.file) << "\"/>\n";
    s << "  </Collection>\n</VTKFile>\n";
    writeTextAtomically(pvdPath(), s.str());
}

std::vector<FrameEntry> Series::readPvd(const std::string& dir, const std::string& name,
                                        double time) {
    std::vector<FrameEntry> out;
    std::ifstream f(dir + "/" + name + ".pvd");
    if (!f) return out;
    // Our own format (writePvd): one DataSet element a line, timestep written exactly.
    std::string line;
    const std::string prefix = name + "_";
    while (std::getline(f, line)) {
        const auto t = line.find("timestep=\"");
        const auto fl = line.find("file=\"");
        if (t == std::string::npos || fl == std::string::npos) continue;
        FrameEntry e;
        e.time = std::strtod(line.c_str() + t + 10, nullptr);
        const auto end = line.find('"', fl + 6);
        if (end == std::string::npos) continue;
        e.file = line.substr(fl + 6, end - fl - 6);
        if (e.file.compare(0, prefix.size(), prefix) != 0)
            throw Error("vtk: '" + dir + "/" + name + ".pvd' lists '" + e.file +
                        "', not a frame of series '" + name +
                        "' (append needs a .pvd written by "
                        "m:vtk)");
        e.frame = std::strtoll(e.file.c_str() + prefix.size(), nullptr, 10);
        e.step = -1;  // not in the .pvd
        if (e.time <= time) out.push_back(e);
    }
    return out;
}

}  // namespace talus::vtk
