//! Parsing a scene: the objects are read one by one as the text is read (a scene of a
//! million objects never exists as a JSON tree), and every error names the field at fault.

use super::{Result, Scene, SceneError, SceneObject, ShapeSpec};
use glam::{DQuat, DVec3};
use kinetic_core::{Response, Walls, WorldKind};
use kinetic_spheres::PeriodicBox;
use serde::de::{DeserializeSeed, Deserializer as _, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde_json::{Map, Value};
use std::fmt;

impl Scene {
    /// Parses and checks a scene from JSON text (a leading byte-order mark is skipped). The
    /// objects are read one at a time, so memory holds the scene, not a tree of the text.
    pub fn from_json(text: &str) -> Result<Scene> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        if text.trim().is_empty() {
            return Err(SceneError::new(
                "scene",
                "the file is empty (expected a JSON object)",
            ));
        }
        let mut de = serde_json::Deserializer::from_str(text);
        let read = de
            .deserialize_any(TopVisitor)
            .and_then(|read| de.end().map(|()| read))
            .map_err(|e| json_error(&e, text))?;
        let Read::Top { rest: top, objects } = read else {
            return Err(SceneError::new("scene", "must be a JSON object"));
        };
        only_keys(
            &top,
            "",
            &[
                "world", "horizon", "response", "walls", "periodic", "objects",
            ],
        )?;
        let world = match string(required(&top, "", "world")?, "world")? {
            "free" => WorldKind::Free,
            "plane" => WorldKind::Plane,
            other => {
                return Err(SceneError::new(
                    "world",
                    format!("must be \"free\" or \"plane\", got {other:?}"),
                ));
            }
        };
        let horizon = number(required(&top, "", "horizon")?, "horizon")?;
        if horizon <= 0.0 {
            return Err(SceneError::new(
                "horizon",
                format!("must be > 0, got {horizon}"),
            ));
        }
        let response = match top.get("response") {
            None => Response::None,
            Some(v) => match string(v, "response")? {
                "none" => Response::None,
                "elastic" => Response::Elastic,
                other => {
                    return Err(SceneError::new(
                        "response",
                        format!("must be \"none\" or \"elastic\", got {other:?}"),
                    ));
                }
            },
        };
        let walls = top
            .get("walls")
            .map(|v| parse_walls(v, world))
            .transpose()?;
        let periodic = top
            .get("periodic")
            .map(|v| parse_periodic(v, world, response, walls.is_some()))
            .transpose()?;
        let objects = match objects {
            None => return Err(SceneError::new("objects", "missing required field")),
            Some(Objects::NotArray) => return Err(SceneError::new("objects", "must be an array")),
            Some(Objects::Bad(e)) => return Err(e),
            Some(Objects::List(list)) => list,
        };
        for (i, obj) in objects.iter().enumerate() {
            check_object(obj, i, world, response, walls.as_ref())?;
            if let Some(p) = &periodic {
                check_periodic_object(obj, i, p)?;
            }
        }
        let scene = Scene {
            world,
            horizon,
            response,
            walls,
            periodic,
            objects,
        };
        scene.check_range()?;
        Ok(scene)
    }
}

/// The document as read: its top-level fields but `objects`, and the objects.
enum Read {
    Top {
        rest: Map<String, Value>,
        objects: Option<Objects>,
    },
    NotObject,
}

/// The `objects` field as read.
enum Objects {
    List(Vec<SceneObject>),
    NotArray,
    /// The first object that is wrong (the rest of the array is read over).
    Bad(SceneError),
}

struct TopVisitor;

impl<'de> Visitor<'de> for TopVisitor {
    type Value = Read;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON object")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<Read, A::Error> {
        let mut rest = Map::new();
        let mut objects = None;
        while let Some(key) = map.next_key::<String>()? {
            // serde_json hands a number of arbitrary precision over as a map of this one key.
            if key.starts_with("$serde_json::") {
                map.next_value::<IgnoredAny>()?;
                return Ok(Read::NotObject);
            }
            if key == "objects" {
                objects = Some(map.next_value_seed(ObjectsSeed)?);
            } else {
                let value: Value = map.next_value()?;
                rest.insert(key, value);
            }
        }
        Ok(Read::Top { rest, objects })
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> std::result::Result<Read, A::Error> {
        while seq.next_element::<IgnoredAny>()?.is_some() {}
        Ok(Read::NotObject)
    }

    fn visit_bool<E>(self, _: bool) -> std::result::Result<Read, E> {
        Ok(Read::NotObject)
    }
    fn visit_i64<E>(self, _: i64) -> std::result::Result<Read, E> {
        Ok(Read::NotObject)
    }
    fn visit_u64<E>(self, _: u64) -> std::result::Result<Read, E> {
        Ok(Read::NotObject)
    }
    fn visit_f64<E>(self, _: f64) -> std::result::Result<Read, E> {
        Ok(Read::NotObject)
    }
    fn visit_str<E>(self, _: &str) -> std::result::Result<Read, E> {
        Ok(Read::NotObject)
    }
    fn visit_unit<E>(self) -> std::result::Result<Read, E> {
        Ok(Read::NotObject)
    }
}

struct ObjectsSeed;

impl<'de> DeserializeSeed<'de> for ObjectsSeed {
    type Value = Objects;

    fn deserialize<D: serde::Deserializer<'de>>(
        self,
        d: D,
    ) -> std::result::Result<Objects, D::Error> {
        d.deserialize_any(ObjectsVisitor)
    }
}

struct ObjectsVisitor;

impl<'de> Visitor<'de> for ObjectsVisitor {
    type Value = Objects;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array of objects")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> std::result::Result<Objects, A::Error> {
        let mut list = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 20));
        let mut bad = None;
        while let Some(value) = seq.next_element::<Value>()? {
            if bad.is_none() {
                // The path is written only for an object at fault: parsed again with it.
                match parse_object(&value, "") {
                    Ok(obj) => list.push(obj),
                    Err(e) => {
                        let path = format!("objects[{}]", list.len());
                        bad = Some(parse_object(&value, &path).err().unwrap_or(e));
                    }
                }
            }
        }
        Ok(match bad {
            Some(e) => Objects::Bad(e),
            None => Objects::List(list),
        })
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<Objects, A::Error> {
        while map.next_entry::<IgnoredAny, IgnoredAny>()?.is_some() {}
        Ok(Objects::NotArray)
    }
    fn visit_bool<E>(self, _: bool) -> std::result::Result<Objects, E> {
        Ok(Objects::NotArray)
    }
    fn visit_i64<E>(self, _: i64) -> std::result::Result<Objects, E> {
        Ok(Objects::NotArray)
    }
    fn visit_u64<E>(self, _: u64) -> std::result::Result<Objects, E> {
        Ok(Objects::NotArray)
    }
    fn visit_f64<E>(self, _: f64) -> std::result::Result<Objects, E> {
        Ok(Objects::NotArray)
    }
    fn visit_str<E>(self, _: &str) -> std::result::Result<Objects, E> {
        Ok(Objects::NotArray)
    }
    fn visit_unit<E>(self) -> std::result::Result<Objects, E> {
        Ok(Objects::NotArray)
    }
}

/// A JSON syntax error, said for people.
fn json_error(e: &serde_json::Error, text: &str) -> SceneError {
    let hint = if ["NaN", "Infinity"].iter().any(|w| text.contains(w)) {
        " (numbers must be finite: NaN and Infinity are not JSON)"
    } else {
        ""
    };
    SceneError::new("scene", format!("not valid JSON: {e}{hint}"))
}

fn object<'a>(v: &'a Value, path: &str) -> Result<&'a Map<String, Value>> {
    v.as_object()
        .ok_or_else(|| SceneError::new(path, "must be a JSON object"))
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

fn only_keys(m: &Map<String, Value>, path: &str, allowed: &[&str]) -> Result<()> {
    match m.keys().find(|k| !allowed.contains(&k.as_str())) {
        Some(k) => Err(SceneError::new(
            join(path, k),
            format!("unknown field (expected one of: {})", allowed.join(", ")),
        )),
        None => Ok(()),
    }
}

fn required<'a>(m: &'a Map<String, Value>, path: &str, key: &str) -> Result<&'a Value> {
    m.get(key)
        .ok_or_else(|| SceneError::new(join(path, key), "missing required field"))
}

fn string<'a>(v: &'a Value, path: &str) -> Result<&'a str> {
    v.as_str()
        .ok_or_else(|| SceneError::new(path, "must be a string"))
}

fn number(v: &Value, path: &str) -> Result<f64> {
    finite(v).map_err(|why| SceneError::new(path, why))
}

/// A finite number, or what is wrong with it (the path is only written for an error: a
/// scene of 100,000 objects has a million numbers).
fn finite(v: &Value) -> std::result::Result<f64, String> {
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(format!("must be a finite number, got {n}")),
        },
        _ => Err("must be a number".to_string()),
    }
}

fn numbers<const N: usize>(v: &Value, path: &str) -> Result<[f64; N]> {
    let list = v
        .as_array()
        .filter(|a| a.len() == N)
        .ok_or_else(|| SceneError::new(path, format!("must be an array of {N} numbers")))?;
    let mut out = [0.0; N];
    for (i, x) in list.iter().enumerate() {
        out[i] = finite(x).map_err(|why| SceneError::new(format!("{path}[{i}]"), why))?;
    }
    Ok(out)
}

fn vec3(v: &Value, path: &str) -> Result<DVec3> {
    numbers::<3>(v, path).map(DVec3::from_array)
}

fn optional_vec3(m: &Map<String, Value>, path: &str, key: &str) -> Result<DVec3> {
    m.get(key)
        .map_or(Ok(DVec3::ZERO), |v| vec3(v, &join(path, key)))
}

fn parse_walls(v: &Value, world: WorldKind) -> Result<Walls> {
    let m = object(v, "walls")?;
    only_keys(m, "walls", &["min", "max"])?;
    let min = vec3(required(m, "walls", "min")?, "walls.min")?;
    let max = vec3(required(m, "walls", "max")?, "walls.max")?;
    let dims = if world == WorldKind::Plane { 2 } else { 3 };
    if let Some(k) = (0..dims).find(|&k| min[k] >= max[k]) {
        return Err(SceneError::new(
            format!("walls.max[{k}]"),
            format!(
                "must be greater than walls.min[{k}] ({} <= {})",
                max[k], min[k]
            ),
        ));
    }
    Ok(Walls { min, max })
}

fn parse_object(v: &Value, path: &str) -> Result<SceneObject> {
    let m = object(v, path)?;
    only_keys(
        m,
        path,
        &[
            "shape",
            "position",
            "velocity",
            "acceleration",
            "orientation",
            "angular_velocity",
        ],
    )?;
    let shape = parse_shape(required(m, path, "shape")?, &join(path, "shape"))?;
    let position = vec3(required(m, path, "position")?, &join(path, "position"))?;
    let orientation = match m.get("orientation") {
        None => DQuat::IDENTITY,
        Some(v) => {
            let p = join(path, "orientation");
            let q = DQuat::from_array(numbers::<4>(v, &p)?);
            if (q.length() - 1.0).abs() > 1e-6 {
                return Err(SceneError::new(
                    p,
                    format!(
                        "must be a unit quaternion [x, y, z, w], its norm is {}",
                        q.length()
                    ),
                ));
            }
            q.normalize()
        }
    };
    Ok(SceneObject {
        shape,
        position,
        velocity: optional_vec3(m, path, "velocity")?,
        acceleration: optional_vec3(m, path, "acceleration")?,
        orientation,
        angular_velocity: optional_vec3(m, path, "angular_velocity")?,
    })
}

fn parse_shape(v: &Value, path: &str) -> Result<ShapeSpec> {
    let m = object(v, path)?;
    only_keys(m, path, &["ball", "cuboid", "convex_hull"])?;
    if m.len() != 1 {
        return Err(SceneError::new(
            path,
            "must hold exactly one of ball, cuboid, convex_hull",
        ));
    }
    let (kind, body) = m.iter().next().expect("one entry");
    let p = join(path, kind);
    let inner = object(body, &p)?;
    let positive = |x: f64, at: &str| {
        if x > 0.0 {
            Ok(x)
        } else {
            Err(SceneError::new(at, format!("must be > 0, got {x}")))
        }
    };
    match kind.as_str() {
        "ball" => {
            only_keys(inner, &p, &["radius"])?;
            let at = join(&p, "radius");
            let r = number(required(inner, &p, "radius")?, &at)?;
            Ok(ShapeSpec::Ball {
                radius: positive(r, &at)?,
            })
        }
        "cuboid" => {
            only_keys(inner, &p, &["half_extents"])?;
            let at = join(&p, "half_extents");
            let h = vec3(required(inner, &p, "half_extents")?, &at)?;
            for k in 0..3 {
                positive(h[k], &format!("{at}[{k}]"))?;
            }
            Ok(ShapeSpec::Cuboid { half_extents: h })
        }
        _ => {
            only_keys(inner, &p, &["points"])?;
            let at = join(&p, "points");
            let list = required(inner, &p, "points")?
                .as_array()
                .ok_or_else(|| SceneError::new(&at, "must be an array of [x, y, z] points"))?;
            if list.len() < 4 {
                return Err(SceneError::new(
                    &at,
                    format!("needs at least 4 points, got {}", list.len()),
                ));
            }
            let points = list
                .iter()
                .enumerate()
                .map(|(i, v)| vec3(v, &format!("{at}[{i}]")))
                .collect::<Result<Vec<_>>>()?;
            if is_flat(&points) {
                return Err(SceneError::new(
                    &at,
                    "the points are coplanar (the hull is flat or degenerate)",
                ));
            }
            Ok(ShapeSpec::ConvexHull { points })
        }
    }
}

/// Whether all points lie (up to rounding) in one plane.
fn is_flat(points: &[DVec3]) -> bool {
    let p0 = points[0];
    let scale = points
        .iter()
        .map(|p| (*p - p0).length())
        .fold(0.0, f64::max);
    if scale == 0.0 {
        return true;
    }
    let far = |f: &dyn Fn(DVec3) -> f64| {
        points
            .iter()
            .copied()
            .max_by(|a, b| f(*a).total_cmp(&f(*b)))
            .unwrap_or(p0)
    };
    let p1 = far(&|p| (p - p0).length());
    let p2 = far(&|p| (p - p0).cross(p1 - p0).length());
    let n = (p1 - p0).cross(p2 - p0);
    let volume = points
        .iter()
        .map(|p| (*p - p0).dot(n).abs())
        .fold(0.0, f64::max);
    volume <= 1e-12 * scale * scale * scale
}

fn parse_periodic(
    v: &Value,
    world: WorldKind,
    response: Response,
    walls: bool,
) -> Result<PeriodicBox> {
    let m = object(v, "periodic")?;
    only_keys(m, "periodic", &["min", "max"])?;
    let min = vec3(required(m, "periodic", "min")?, "periodic.min")?;
    let max = vec3(required(m, "periodic", "max")?, "periodic.max")?;
    for k in 0..3 {
        if max[k] <= min[k] {
            return Err(SceneError::new(
                format!("periodic.max[{k}]"),
                format!(
                    "must be greater than periodic.min[{k}] ({} <= {})",
                    max[k], min[k]
                ),
            ));
        }
    }
    let why = if world != WorldKind::Free {
        Some("applies to \"free\" worlds only")
    } else if response != Response::Elastic {
        Some("needs the \"elastic\" response (balls that bounce off each other)")
    } else if walls {
        Some("cannot be combined with walls")
    } else {
        None
    };
    match why {
        Some(why) => Err(SceneError::new("periodic", why)),
        None => Ok(PeriodicBox { min, max }),
    }
}

/// In a periodic box: a ball moving linearly, its centre inside the box.
fn check_periodic_object(o: &SceneObject, i: usize, p: &PeriodicBox) -> Result<()> {
    let path = format!("objects[{i}]");
    if o.acceleration != DVec3::ZERO {
        return Err(SceneError::new(
            format!("{path}.acceleration"),
            "balls in a periodic box move linearly (no acceleration)",
        ));
    }
    for k in 0..3 {
        let c = o.position[k];
        if c < p.min[k] || c > p.max[k] {
            return Err(SceneError::new(
                format!("{path}.position[{k}]"),
                "the centre starts outside the periodic box",
            ));
        }
    }
    Ok(())
}

fn check_object(
    o: &SceneObject,
    i: usize,
    world: WorldKind,
    response: Response,
    walls: Option<&Walls>,
) -> Result<()> {
    let path = format!("objects[{i}]");
    let ShapeSpec::Ball { radius } = o.shape else {
        if world == WorldKind::Plane {
            return Err(SceneError::new(
                format!("{path}.shape"),
                "a \"plane\" world holds balls only",
            ));
        }
        if response == Response::Elastic {
            return Err(SceneError::new(
                format!("{path}.shape"),
                "the \"elastic\" response applies to balls only",
            ));
        }
        return Ok(());
    };
    if let Some(w) = walls.filter(|_| response == Response::Elastic) {
        let dims = if world == WorldKind::Plane { 2 } else { 3 };
        for k in 0..dims {
            let p = o.position[k];
            if p - radius < w.min[k] || p + radius > w.max[k] {
                return Err(SceneError::new(
                    format!("{path}.position[{k}]"),
                    format!("the ball (radius {radius}) starts outside the walls"),
                ));
            }
        }
    }
    Ok(())
}
