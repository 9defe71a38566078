// floor_contacts: box nodes within the speculative margin of the floor (collision/pipeline.h).
#include "collision/margins.h"
#include "collision/pipeline.h"

#include <algorithm>
#include <cmath>

namespace ffd::detail {

void findFloorContacts(CollisionWorld& w) {
    CollisionState& s = w.collision;
    s.all.resize(s.objectCount);
    w.profile.floorContacts = 0;
    if (!w.settings.floor) return;
    // On one thread: the contacts are few per body and cheap to make, and on several threads
    // their copies into place cost more than making them (measured on alphabets).
    const float floorY = w.settings.floorHeight;
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const CollisionBody& r = w.bodies[b];
        const float skin = skinOf(w, r) + w.substep * r.maxSpeed;
        if (r.bounds.lo.y >= floorY + skin) continue;
        const Lattice& L = *r.lattice;
        for (uint32_t k = 0; k < r.boxCount; ++k) {
            if (w.boxBounds[r.firstBox + k].lo.y >= floorY + skin) continue;
            const CellBox& box = L.boxes[k];
            for (int n = 0; n < 8; ++n) {
                const uint32_t node = (r.firstBox + k) * 8 + uint32_t(n);
                const float y = w.nodes[node].y;
                if (y >= floorY + skin) continue;
                Contact c;
                c.bodyA = b;
                c.nodeA = node;
                c.normal = {0, 1, 0};
                c.offset = floorY;
                c.distance = y - floorY;
                setPushOut(w, r, b, kFloorBody, c);
                c.friction = r.friction;
                c.restitution = r.restitution;
                c.rigidity = r.contactRigidity;
                makeContactPoint(L.cellParticles[box.cell].data(), r.firstParticle,
                                 box.nodeLocal(n), w.invMass, c.a, c.invMassA);
                s.all.push_back(c);
            }
        }
    }
    w.profile.floorContacts = int(s.all.size() - s.objectCount);
}

} // namespace ffd::detail
