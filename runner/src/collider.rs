//! The collider ball: it sits on the scene's surface, is driven by keys in the viewer
//! or along a scripted path (`--collider-path`) in both viewer and headless render.

use glam::{Vec2, Vec3, Vec4};
use shared::query::{Around, Question, Sight};
use shared::world::mesh::SurfacePoint;
use shared::world::mesh::bvh::IndexedMesh;

/// How deep the ball sinks into the grass: its centre is this fraction of its radius
/// above the surface, so it presses the blades down rather than rolling over them.
const SINK: f32 = 0.6;

/// A ball resting on a surface.
#[derive(Copy, Clone, Debug)]
pub struct Ball {
    /// Where it touches the surface, and the surface normal there.
    pub contact: SurfacePoint,
    /// Radius in scene units.
    pub radius: f32,
}

impl Ball {
    /// A ball of `radius` dropped onto `mesh` above (x, z) (see [`drop_onto`]).
    pub fn dropped(mesh: &IndexedMesh, xz: Vec2, radius: f32) -> Option<Self> {
        drop_onto(mesh, xz).map(|contact| Self { contact, radius })
    }

    /// The sphere collider: centre (xyz) and radius (w).
    pub fn sphere(&self) -> Vec4 {
        (self.contact.position + self.contact.normal * self.radius * SINK).extend(self.radius)
    }

    /// What the viewer asks of the grass about the ball (`shared::query`): the blades
    /// around where it touches the ground, within its radius, and how hidden its
    /// centre is from `eye` (a sight as wide as a tenth of the ball).
    pub fn questions(&self, eye: Vec3) -> [Question; 2] {
        [
            Question::around(Around {
                centre: self.contact.position,
                radius: self.radius,
            }),
            Question::sight(Sight {
                from: eye,
                to: self.sphere().truncate(),
                radius: 0.1 * self.radius,
            }),
        ]
    }

    /// Slides the ball by `delta` along the surface: moves in the tangent plane, then
    /// settles on the nearest point of `mesh`.
    pub fn slide(&mut self, mesh: &IndexedMesh, delta: Vec3) {
        let n = self.contact.normal;
        let tangent = delta - n * n.dot(delta);
        if let Some(p) = mesh.closest_point(self.contact.position + tangent) {
            self.contact = p;
        }
    }
}

/// Drops a point from high above (x, z) straight down onto `mesh`; where nothing is
/// below, the nearest point of the mesh. Both through the mesh's hierarchy: a few
/// dozen triangles looked at, not every one.
pub fn drop_onto(mesh: &IndexedMesh, xz: Vec2) -> Option<SurfacePoint> {
    point_below(mesh, xz).or_else(|| {
        let (_, max) = mesh.mesh.bounds()?;
        mesh.closest_point(Vec3::new(xz.x, max.y + 1.0, xz.y))
    })
}

/// The highest point of `mesh` straight under (x, z), if the mesh reaches there: a
/// ray from above it, through the mesh's hierarchy.
pub fn point_below(mesh: &IndexedMesh, xz: Vec2) -> Option<SurfacePoint> {
    let (_, max) = mesh.mesh.bounds()?;
    let above = Vec3::new(xz.x, max.y + 1.0, xz.y);
    mesh.ray_hit(above, Vec3::NEG_Y)
}

/// A polyline in the ground plane (x, z) the ball follows at a constant speed, then
/// stays at its end.
#[derive(Clone, Debug, PartialEq)]
pub struct ColliderPath {
    /// The corners, in order.
    pub points: Vec<Vec2>,
}

impl std::fmt::Display for ColliderPath {
    /// "x,z;x,z;...", as [`ColliderPath::parse`] reads it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let points: Vec<String> = self
            .points
            .iter()
            .map(|p| format!("{},{}", p.x, p.y))
            .collect();
        write!(f, "{}", points.join(";"))
    }
}

impl ColliderPath {
    /// Parses "x,z x,z ..." (at least two points, separated by spaces or `;`).
    pub fn parse(s: &str) -> Result<Self, String> {
        let points = s
            .split(|c: char| c.is_whitespace() || c == ';')
            .filter(|p| !p.is_empty())
            .map(|p| {
                let xz = crate::parse::parse_coordinates::<2>(p)?;
                Ok(Vec2::new(xz[0], xz[1]))
            })
            .collect::<Result<Vec<_>, String>>()?;
        if points.len() < 2 {
            return Err(format!(
                "a collider path needs at least two points \"x,z x,z\", got {}",
                points.len()
            ));
        }
        Ok(Self { points })
    }

    /// The position after travelling `distance` along the path.
    pub fn at(&self, distance: f32) -> Vec2 {
        let mut left = distance.max(0.0);
        for pair in self.points.windows(2) {
            let length = pair[0].distance(pair[1]);
            if left <= length && length > 0.0 {
                return pair[0].lerp(pair[1], left / length);
            }
            left -= length;
        }
        self.points.last().copied().unwrap_or_default()
    }

    /// Total length.
    pub fn length(&self) -> f32 {
        self.points.windows(2).map(|p| p[0].distance(p[1])).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_is_walked_at_constant_speed_and_stops_at_its_end() {
        let path = ColliderPath::parse("0,0 3,4;3,0").unwrap();
        assert_eq!(path.length(), 9.0);
        assert_eq!(path.at(0.0), Vec2::ZERO);
        assert!((path.at(2.5) - Vec2::new(1.5, 2.0)).length() < 1e-6);
        assert!((path.at(7.0) - Vec2::new(3.0, 2.0)).length() < 1e-6);
        assert_eq!(path.at(100.0), Vec2::new(3.0, 0.0));
    }

    #[test]
    fn the_ball_slides_along_a_plane_and_stays_on_a_planet() {
        let plane = IndexedMesh::new(crate::scene::builtin::plane(10.0, 4));
        let mut ball = Ball {
            contact: drop_onto(&plane, Vec2::new(1.0, 2.0)).unwrap(),
            radius: 1.5,
        };
        assert!((ball.contact.position - Vec3::new(1.0, 0.0, 2.0)).length() < 1e-5);
        // The vertical part of a move is dropped: it slides on the ground.
        ball.slide(&plane, Vec3::new(0.5, 3.0, 0.0));
        assert!((ball.contact.position - Vec3::new(1.5, 0.0, 2.0)).length() < 1e-5);
        assert!((ball.sphere() - Vec4::new(1.5, 0.9, 2.0, 1.5)).length() < 1e-5);

        let planet = IndexedMesh::new(crate::scene::builtin::sphere(Vec3::ZERO, 5.0, 4));
        let mut ball = Ball {
            contact: drop_onto(&planet, Vec2::ZERO).unwrap(),
            radius: 1.0,
        };
        assert!(ball.contact.position.y > 4.9);
        for _ in 0..100 {
            ball.slide(&planet, Vec3::new(0.2, 0.0, 0.0));
            let r = ball.contact.position.length();
            assert!((4.9..=5.0 + 1e-4).contains(&r), "off the surface: {r}");
            assert!(ball.contact.normal.dot(ball.contact.position.normalize()) > 0.99);
        }
        // It went round the planet's side, not off into space.
        assert!(ball.contact.position.y < 4.0);
    }

    #[test]
    fn bad_paths_are_refused_with_a_reason() {
        assert!(
            ColliderPath::parse("1,2")
                .unwrap_err()
                .contains("two points")
        );
        assert!(ColliderPath::parse("1,2 x,3").is_err());
        assert!(ColliderPath::parse("1,2 3").is_err());
        assert!(ColliderPath::parse("1,2 nan,3").is_err());
    }
}
