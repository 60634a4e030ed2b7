//! Scene files (`../shared/scene-format.md`): parsing with errors that name the object and
//! field at fault, and turning a scene into a [`World`].

use glam::{DQuat, DVec3};
use kinetic_core::{FlightPlan, Response, Walls, WorldKind};
use serde_json::{Map, Value};

/// The shape of a scene object.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeSpec {
    /// A ball.
    Ball {
        /// Its radius.
        radius: f64,
    },
    /// A box.
    Cuboid {
        /// Half its size along each axis of its own frame.
        half_extents: DVec3,
    },
    /// The convex hull of points given in the object's own frame.
    ConvexHull {
        /// The points.
        points: Vec<DVec3>,
    },
}

/// One object of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneObject {
    /// Its shape.
    pub shape: ShapeSpec,
    /// Its centre (its frame's origin) at t = 0; in a plane world, the tangency point.
    pub position: DVec3,
    /// Its velocity at t = 0.
    pub velocity: DVec3,
    /// Its constant acceleration.
    pub acceleration: DVec3,
    /// Its orientation at t = 0.
    pub orientation: DQuat,
    /// Its constant spin.
    pub angular_velocity: DVec3,
}

impl SceneObject {
    /// A ball with a linear motion.
    pub fn ball(radius: f64, position: DVec3, velocity: DVec3) -> SceneObject {
        SceneObject {
            shape: ShapeSpec::Ball { radius },
            position,
            velocity,
            acceleration: DVec3::ZERO,
            orientation: DQuat::IDENTITY,
            angular_velocity: DVec3::ZERO,
        }
    }

    /// Its flight plan from t = 0.
    pub fn plan(&self) -> FlightPlan {
        FlightPlan::accelerated(self.position, self.velocity, self.acceleration)
            .with_spin(self.orientation, self.angular_velocity)
    }

    /// The plan of its centre in 3-space: its plan in a free world; in a plane world the
    /// rolling ball's centre, its radius above the tangency point, moving in x and y.
    pub fn centre_plan(&self, world: WorldKind) -> FlightPlan {
        match world {
            WorldKind::Free => self.plan(),
            WorldKind::Plane => FlightPlan::accelerated(
                self.position.with_z(outer_radius(&self.shape)),
                self.velocity.with_z(0.0),
                self.acceleration.with_z(0.0),
            ),
        }
    }
}

/// A scene: a world, a horizon, a response, optional walls and the objects.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Free flight or rolling on a plane.
    pub world: WorldKind,
    /// The run covers `[0, horizon]`.
    pub horizon: f64,
    /// What happens at contact.
    pub response: Response,
    /// The box that holds the scene, if any.
    pub walls: Option<Walls>,
    /// The objects; object `i` is named by its index.
    pub objects: Vec<SceneObject>,
}

/// What is wrong with a scene: the field at fault (`objects[3].shape.ball.radius`) and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{path}: {message}")]
pub struct SceneError {
    /// Where: a path such as `objects[3].velocity[1]` (empty for the whole document).
    pub path: String,
    /// What is wrong.
    pub message: String,
}

impl SceneError {
    fn new(path: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError {
            path: path.into(),
            message: message.into(),
        }
    }

    /// The index of the object at fault, if the error is inside `objects`.
    pub fn object(&self) -> Option<usize> {
        let rest = self.path.strip_prefix("objects[")?;
        rest[..rest.find(']')?].parse().ok()
    }
}

type Result<T> = std::result::Result<T, SceneError>;

impl Scene {
    /// Parses and checks a scene from JSON text.
    pub fn from_json(text: &str) -> Result<Scene> {
        let value: Value = serde_json::from_str(text).map_err(|e| {
            SceneError::new(
                "scene",
                format!("not valid JSON: {e} (numbers must be finite)"),
            )
        })?;
        let top = object(&value, "scene")?;
        only_keys(
            top,
            "",
            &["world", "horizon", "response", "walls", "objects"],
        )?;
        let world = match string(required(top, "", "world")?, "world")? {
            "free" => WorldKind::Free,
            "plane" => WorldKind::Plane,
            other => {
                return Err(SceneError::new(
                    "world",
                    format!("must be \"free\" or \"plane\", got {other:?}"),
                ));
            }
        };
        let horizon = number(required(top, "", "horizon")?, "horizon")?;
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
        let list = required(top, "", "objects")?
            .as_array()
            .ok_or_else(|| SceneError::new("objects", "must be an array"))?;
        let mut objects = Vec::with_capacity(list.len());
        for (i, v) in list.iter().enumerate() {
            let obj = parse_object(v, &format!("objects[{i}]"))?;
            check_object(&obj, i, world, response, walls.as_ref())?;
            objects.push(obj);
        }
        Ok(Scene {
            world,
            horizon,
            response,
            walls,
            objects,
        })
    }

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
        top.insert("objects".into(), Value::Array(objects));
        let mut text = serde_json::to_string_pretty(&Value::Object(top)).unwrap_or_default();
        text.push('\n');
        text
    }

    /// The largest ratio between two objects' outer radii (1 for fewer than two objects).
    pub fn size_ratio(&self) -> f64 {
        let radii = self.objects.iter().map(|o| outer_radius(&o.shape));
        let (lo, hi) = radii.fold((f64::INFINITY, 0.0f64), |(lo, hi), r| {
            (lo.min(r), hi.max(r))
        });
        if self.objects.len() < 2 { 1.0 } else { hi / lo }
    }
}

/// The radius of the ball around the object's origin that holds the shape.
pub fn outer_radius(shape: &ShapeSpec) -> f64 {
    match shape {
        ShapeSpec::Ball { radius } => *radius,
        ShapeSpec::Cuboid { half_extents } => half_extents.length(),
        ShapeSpec::ConvexHull { points } => points.iter().map(|p| p.length()).fold(0.0, f64::max),
    }
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
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.is_finite() => Ok(x),
            _ => Err(SceneError::new(
                path,
                format!("must be a finite number, got {n}"),
            )),
        },
        _ => Err(SceneError::new(path, "must be a number")),
    }
}

fn numbers<const N: usize>(v: &Value, path: &str) -> Result<[f64; N]> {
    let list = v
        .as_array()
        .filter(|a| a.len() == N)
        .ok_or_else(|| SceneError::new(path, format!("must be an array of {N} numbers")))?;
    let mut out = [0.0; N];
    for (i, x) in list.iter().enumerate() {
        out[i] = number(x, &format!("{path}[{i}]"))?;
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
