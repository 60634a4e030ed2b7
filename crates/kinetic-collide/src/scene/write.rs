//! A scene as JSON text.

use super::{Scene, ShapeSpec};
use glam::{DQuat, DVec3};
use kinetic_core::{Response, WorldKind};
use serde_json::{Map, Value};

impl Scene {
    /// The scene as JSON text, in the scene format (round-trips through [`Scene::from_json`]).
    pub fn to_json(&self) -> String {
        let v3 = |v: DVec3| serde_json::json!([v.x, v.y, v.z]);
        let objects: Vec<Value> = self
            .objects
            .iter()
            .map(|o| {
                let shape = match &o.shape {
                    ShapeSpec::Ball { radius } => serde_json::json!({"ball": {"radius": radius}}),
                    ShapeSpec::Cuboid { half_extents } => {
                        serde_json::json!({"cuboid": {"half_extents": v3(*half_extents)}})
                    }
                    ShapeSpec::ConvexHull { points } => {
                        serde_json::json!({"convex_hull": {"points": points.iter().map(|p| v3(*p)).collect::<Vec<_>>()}})
                    }
                };
                let mut m = Map::new();
                m.insert("shape".into(), shape);
                m.insert("position".into(), v3(o.position));
                m.insert("velocity".into(), v3(o.velocity));
                if o.acceleration != DVec3::ZERO {
                    m.insert("acceleration".into(), v3(o.acceleration));
                }
                if o.orientation != DQuat::IDENTITY {
                    let q = o.orientation;
                    m.insert("orientation".into(), serde_json::json!([q.x, q.y, q.z, q.w]));
                }
                if o.angular_velocity != DVec3::ZERO {
                    m.insert("angular_velocity".into(), v3(o.angular_velocity));
                }
                Value::Object(m)
            })
            .collect();
        let mut top = Map::new();
        top.insert(
            "world".into(),
            match self.world {
                WorldKind::Free => "free".into(),
                WorldKind::Plane => "plane".into(),
            },
        );
        top.insert("horizon".into(), self.horizon.into());
        top.insert(
            "response".into(),
            match self.response {
                Response::None => "none".into(),
                Response::Elastic => "elastic".into(),
            },
        );
        if let Some(w) = self.walls {
            top.insert(
                "walls".into(),
                serde_json::json!({"min": v3(w.min), "max": v3(w.max)}),
            );
        }
        if let Some(p) = self.periodic {
            top.insert(
                "periodic".into(),
                serde_json::json!({"min": v3(p.min), "max": v3(p.max)}),
            );
        }
        top.insert("objects".into(), Value::Array(objects));
        let mut text = serde_json::to_string_pretty(&Value::Object(top)).unwrap_or_default();
        text.push('\n');
        text
    }
}
