//! `camera { }`.

use glam::Vec3;

use super::expressions::{triple, v3};
use super::keywords::{in_list, keyword, Kw};
use super::{Parser, D, R};
use crate::scene::error::DiagnosticKind as K;
use crate::scene::model::{CameraDesc, Projection};
use crate::scene::token::{Pos, TokenKind as T};

/// Camera items that only affect focal blur: skipped with a warning.
const CAMERA_SKIPPED: &[&str] = &[
    "aperture",
    "blur_samples",
    "focal_point",
    "confidence",
    "variance",
    "bokeh",
    "normal",
];

/// Camera types hfray does not implement (an error: the picture would be
/// different).
const CAMERA_TYPES: &[&str] = &[
    "fisheye",
    "ultra_wide_angle",
    "omnimax",
    "panoramic",
    "spherical",
    "cylinder",
    "mesh_camera",
    "user_defined",
];

impl<'src> Parser<'src, '_> {
    pub(super) fn camera(&mut self) -> R<'src, CameraDesc> {
        let cam_pos = self.bump()?.pos;
        let open = self.open_brace()?;
        let mut cam = CameraDesc::default();
        let mut look_at: Option<Pos> = None;
        let mut where_ = [cam_pos; 4]; // right, up, direction, sky
                                       // Bound: each iteration consumes an item or `}`.
        loop {
            let tok = self.tok;
            match tok.kind {
                T::RBrace => {
                    self.bump()?;
                    break;
                }
                T::Eof => return Err(D::error(open, K::UnterminatedBlock { block: "camera" })),
                T::Hash => self.directive()?,
                T::Ident(name) => match keyword(name) {
                    Some(Kw::Perspective) => {
                        self.bump()?;
                        cam.projection = Projection::Perspective;
                    }
                    Some(Kw::Orthographic) => {
                        self.bump()?;
                        cam.projection = Projection::Orthographic;
                    }
                    Some(Kw::Location) => {
                        self.bump()?;
                        cam.location = v3(self.vector("the camera location (3-vector)")?.0);
                    }
                    Some(Kw::LookAt) => {
                        self.bump()?;
                        cam.look_at = v3(self.vector("the look_at point (3-vector)")?.0);
                        look_at = Some(tok.pos);
                    }
                    Some(Kw::Angle) => {
                        self.bump()?;
                        let (a, pos) = self.float32("the viewing angle in degrees (a float)")?;
                        if a <= 0.0 || a >= 180.0 {
                            return Err(D::error(
                                pos,
                                K::OutOfRange {
                                    what: "camera angle",
                                    range: "in (0, 180) degrees",
                                    value: f64::from(a),
                                },
                            ));
                        }
                        cam.angle = Some(a);
                    }
                    Some(k @ (Kw::Right | Kw::Up | Kw::Direction | Kw::Sky)) => {
                        self.bump()?;
                        let v = v3(self.vector("a camera vector (3-vector)")?.0);
                        let i = match k {
                            Kw::Right => {
                                cam.right = v;
                                0
                            }
                            Kw::Up => {
                                cam.up = v;
                                1
                            }
                            Kw::Direction => {
                                cam.direction = v;
                                2
                            }
                            _ => {
                                cam.sky = v;
                                3
                            }
                        };
                        where_[i] = tok.pos;
                    }
                    Some(Kw::Scale | Kw::Rotate | Kw::Translate | Kw::Matrix | Kw::Transform) => {
                        return Err(D::error(
                            tok.pos,
                            K::NotSupported {
                                what: name,
                                hint: "camera transforms are not implemented; place the camera \
                                       with location and look_at",
                            },
                        ))
                    }
                    _ if in_list(name, CAMERA_TYPES) => {
                        return Err(D::error(
                            tok.pos,
                            K::NotSupported {
                                what: name,
                                hint: "only perspective and orthographic cameras are implemented",
                            },
                        ))
                    }
                    _ if in_list(name, CAMERA_SKIPPED) => self.skip_item("camera")?,
                    _ => {
                        return Err(D::error(
                            tok.pos,
                            K::UnknownIdentifier {
                                name,
                                expected: "a camera item (perspective, orthographic, location, \
                                           look_at, angle, right, up, direction, sky) or `}`",
                            },
                        ))
                    }
                },
                _ => return Err(self.expected(
                    "a camera item (location, look_at, angle, right, up, direction, sky) or `}`",
                )),
            }
        }
        // Degenerate cameras, checked once the whole block is known.
        for (i, (v, which)) in [
            (cam.right, "right"),
            (cam.up, "up"),
            (cam.direction, "direction"),
            (cam.sky, "sky"),
        ]
        .into_iter()
        .enumerate()
        {
            if v == Vec3::ZERO {
                return Err(D::error(where_[i], K::CameraZeroVector { which }));
            }
        }
        let at = match look_at {
            Some(pos) => pos,
            None => {
                // POV-Ray looks along `direction` when no look_at is given.
                cam.look_at = cam.location + cam.direction;
                where_[2]
            }
        };
        let dir = cam.look_at.as_dvec3() - cam.location.as_dvec3();
        if dir.length_squared() < 1e-10 {
            return Err(D::error(
                at,
                K::CameraLookAtIsLocation {
                    point: triple(cam.location.as_dvec3()),
                },
            ));
        }
        let sky = cam.sky.as_dvec3();
        if sky.cross(dir).length() <= 1e-9 * sky.length() * dir.length() {
            return Err(D::error(
                at,
                K::CameraParallelToSky {
                    direction: triple(dir),
                    sky: triple(sky),
                },
            ));
        }
        Ok(cam)
    }
}
