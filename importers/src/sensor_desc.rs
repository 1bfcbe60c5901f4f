//! Virtual illuminance sensors (`[[sensor]]`, docs/photometry.md): meters at points of a plane
//! grid or at single points, each measuring the illuminance E = integral of L cos over the
//! hemisphere of its normal. Sensors do not block or reflect light.

use glam::Vec3;

/// Where a sensor's meters are.
#[derive(Clone, Debug, PartialEq)]
pub enum SensorLayout {
    /// One meter.
    Point {
        /// Its position.
        position: Vec3,
    },
    /// A plane grid of `nx` x `ny` meters at the cell centres of a `size` rectangle centred on
    /// `center`, its first side along `u_axis` and its second along `normal x u_axis`.
    Grid {
        /// Centre of the rectangle.
        center: Vec3,
        /// Unit direction of the first side (perpendicular to the normal).
        u_axis: Vec3,
        /// Side lengths (metres).
        size: [f32; 2],
        /// Meters along each side.
        resolution: [u32; 2],
    },
}

/// What each meter measures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum SensorQuantity {
    /// Illuminance on a plane of the sensor's normal (horizontal or vertical illuminance).
    #[default]
    Planar,
    /// Cylindrical illuminance: the mean vertical illuminance over all horizontal directions,
    /// E_z = (1/pi) integral of L sin(theta) over the sphere (theta from the vertical).
    Cylindrical,
    /// Semi-cylindrical illuminance (EN 13201-2, CIE 136: the facial-recognition criterion of
    /// pedestrian areas): the mean illuminance on the curved surface of a vertical half-cylinder
    /// whose middle faces `facing`, E_sc = (1/pi) integral of L sin(theta) (1 + cos(phi)) over the
    /// sphere, phi the horizontal angle between the incident direction and `facing`.
    SemiCylindrical {
        /// Unit horizontal direction the half-cylinder faces.
        facing: Vec3,
    },
}

impl SensorQuantity {
    /// The quantity's name in lighting practice, for CSV headers and map titles.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Planar => "illuminance",
            Self::Cylindrical => "cylindrical illuminance",
            Self::SemiCylindrical { .. } => "semi-cylindrical illuminance",
        }
    }
}

/// One `[[sensor]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorDesc {
    /// Name (output file suffix).
    pub name: String,
    /// The meters.
    pub layout: SensorLayout,
    /// Unit normal of every meter (up: horizontal illuminance; horizontal: vertical illuminance).
    pub normal: Vec3,
    /// Samples per meter.
    pub samples: u32,
    /// Planar, cylindrical or semi-cylindrical illuminance.
    pub quantity: SensorQuantity,
}

impl SensorDesc {
    /// The meter positions, row by row (the second side outer, the first inner).
    pub fn points(&self) -> Vec<Vec3> {
        match &self.layout {
            SensorLayout::Point { position } => vec![*position],
            SensorLayout::Grid { center, u_axis, size, resolution } => {
                let v_axis = self.normal.cross(*u_axis);
                let [nx, ny] = *resolution;
                let mut out = Vec::with_capacity((nx * ny) as usize);
                for j in 0..ny {
                    for i in 0..nx {
                        let s = ((i as f32 + 0.5) / nx as f32 - 0.5) * size[0];
                        let t = ((j as f32 + 0.5) / ny as f32 - 0.5) * size[1];
                        out.push(*center + *u_axis * s + v_axis * t);
                    }
                }
                out
            }
        }
    }
}
