// Native FCL peer for the tori queries (shared/scenes.md, "tori"): the same
// four queries as bench/peers/tori_peer.py runs through python-fcl, called
// from C++ so that the timings hold no Python object per contact.
//
// Input (stdin, one JSON object, written by tori_peer.py --engine fcl-native):
//   {"scene": <the tumble-tori-queries/1 export of `tumble bench --scene tori
//    --export-scene -`>, "distance_at": [bool per pose]}
// Output (stdout, one JSON line): the raw per-pose answers and timings in
// seconds; tori_peer.py turns them into the record's figures, so the
// statistics and the checks against the truth file have one home.
//
// Each query runs from scratch (a new request and result per call) and is
// timed alone with steady_clock around the single fcl call, as the other
// peers time theirs. Build: bench/setup.sh (g++ -O2, Debian's libfcl-dev).

#include <fcl/config.h>
#include <fcl/fcl.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

using json = nlohmann::json;
using Model = fcl::BVHModel<fcl::OBBRSSd>;
using Clock = std::chrono::steady_clock;

namespace {

// "All pairs": far above the 416 pairs of the worst pose (as tori_peer.py).
constexpr std::size_t kAllPairs = 1000000;

std::shared_ptr<Model> build_model(const json& mesh) {
    std::vector<fcl::Vector3d> vertices;
    for (const auto& v : mesh.at("vertices")) {
        vertices.emplace_back(v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>());
    }
    std::vector<fcl::Triangle> triangles;
    for (const auto& t : mesh.at("triangles")) {
        triangles.emplace_back(t.at(0).get<std::size_t>(), t.at(1).get<std::size_t>(),
                               t.at(2).get<std::size_t>());
    }
    auto model = std::make_shared<Model>();
    model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(vertices.size()));
    model->addSubModel(vertices, triangles);
    model->endModel();
    return model;
}

// A pose of the export: unit quaternion [x, y, z, w] and position.
fcl::Transform3d pose_of(const json& pose) {
    const auto& q = pose.at("rotation");
    const auto& p = pose.at("position");
    fcl::Quaterniond rotation(q.at(3).get<double>(), q.at(0).get<double>(), q.at(1).get<double>(),
                              q.at(2).get<double>());
    fcl::Transform3d t = fcl::Transform3d::Identity();
    t.linear() = rotation.toRotationMatrix();
    t.translation() = fcl::Vector3d(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>());
    return t;
}

// Bytes of one model: its BV nodes, triangles and vertices and the object
// itself. FCL 0.7's memUsage computes this sum but returns BVH_OK (0)
// instead, so it is added up here from the same counts.
std::size_t model_bytes(const Model& m) {
    return sizeof(Model) + static_cast<std::size_t>(m.getNumBVs()) * sizeof(fcl::BVNode<fcl::OBBRSSd>) +
           static_cast<std::size_t>(m.num_tris) * sizeof(fcl::Triangle) +
           static_cast<std::size_t>(m.num_vertices) * sizeof(fcl::Vector3d);
}

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

int main() {
    try {
        json input = json::parse(std::cin);
        const json& scene = input.at("scene");
        if (scene.at("format") != "tumble-tori-queries/1") {
            throw std::runtime_error("scene format " + scene.at("format").dump() +
                                     ", expected \"tumble-tori-queries/1\"");
        }
        const json& poses = scene.at("poses");
        const json& distance_at = input.at("distance_at");
        if (distance_at.size() != poses.size()) {
            throw std::runtime_error("distance_at has " + std::to_string(distance_at.size()) +
                                     " entries for " + std::to_string(poses.size()) + " poses");
        }
        auto model_a = build_model(scene.at("mesh"));
        auto model_b = build_model(scene.at("mesh"));
        fcl::CollisionObjectd a(model_a, fcl::Transform3d::Identity());
        fcl::CollisionObjectd b(model_b, fcl::Transform3d::Identity());

        std::vector<double> first, all_pairs, with_contacts, distance, distances;
        std::vector<bool> hit;
        std::vector<std::size_t> counts, counts_with_contacts;
        // One collide call from scratch (a new request and result), timed alone.
        auto timed_collide = [&](std::size_t max_contacts, bool enable_contact, fcl::CollisionResultd& result) {
            fcl::CollisionRequestd request(max_contacts, enable_contact);
            auto start = Clock::now();
            fcl::collide(&a, &b, request, result);
            return seconds_since(start);
        };
        for (std::size_t i = 0; i < poses.size(); ++i) {
            b.setTransform(pose_of(poses[i]));
            b.computeAABB();
            fcl::CollisionResultd boolean, pairs, contacts;
            first.push_back(timed_collide(1, false, boolean));
            hit.push_back(boolean.isCollision());
            all_pairs.push_back(timed_collide(kAllPairs, false, pairs));
            counts.push_back(pairs.numContacts());
            with_contacts.push_back(timed_collide(kAllPairs, true, contacts));
            counts_with_contacts.push_back(contacts.numContacts());
            if (distance_at[i].get<bool>()) {
                fcl::DistanceRequestd request;
                fcl::DistanceResultd result;
                auto start = Clock::now();
                fcl::distance(&a, &b, request, result);
                distance.push_back(seconds_since(start));
                distances.push_back(result.min_distance);
            }
        }
        json out = {
            {"version", FCL_VERSION},
            {"first", first},
            {"hit", hit},
            {"all_pairs", all_pairs},
            {"counts", counts},
            {"with_contacts", with_contacts},
            {"counts_with_contacts", counts_with_contacts},
            {"distance", distance},
            {"distances", distances},
            // Both models: BV nodes, vertices and triangles.
            {"tree_memory_bytes", model_bytes(*model_a) + model_bytes(*model_b)},
        };
        std::cout << out.dump() << std::endl;
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "peer-fcl: " << e.what() << std::endl;
        return 1;
    }
}
