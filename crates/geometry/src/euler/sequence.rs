//! The names of an Euler-angle convention: [`Axis`], the twelve [`Sequence`]s, intrinsic or
//! extrinsic [`Frame`], and the [`Convention`] that pairs them; parsing and display.
//!
//! Pure data: the rotations themselves are in `convert.rs`.

use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt;
use std::str::FromStr;

use glam::{DMat3, DQuat, DVec3, EulerRot};

use super::zyx::{rot_x, rot_y, rot_z};

/// A coordinate axis of a right-handed frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The first axis, `(1, 0, 0)`.
    X,
    /// The second axis, `(0, 1, 0)`.
    Y,
    /// The third axis, `(0, 0, 1)`.
    Z,
}

impl Axis {
    /// All three, in order.
    pub const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

    /// Index of the axis: 0, 1 or 2 (row/column of a matrix, component of a vector).
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The axis with index 0, 1 or 2; `None` for any other index.
    pub const fn from_index(i: usize) -> Option<Axis> {
        match i {
            0 => Some(Axis::X),
            1 => Some(Axis::Y),
            2 => Some(Axis::Z),
            _ => None,
        }
    }

    /// The axis named by `x`, `y` or `z` (either case); `None` for any other character.
    pub const fn from_char(c: char) -> Option<Axis> {
        match c {
            'x' | 'X' => Some(Axis::X),
            'y' | 'Y' => Some(Axis::Y),
            'z' | 'Z' => Some(Axis::Z),
            _ => None,
        }
    }

    /// The lower-case name: `'x'`, `'y'` or `'z'`.
    pub const fn name(self) -> char {
        match self {
            Axis::X => 'x',
            Axis::Y => 'y',
            Axis::Z => 'z',
        }
    }

    /// The unit vector along the axis.
    pub const fn unit(self) -> DVec3 {
        match self {
            Axis::X => DVec3::X,
            Axis::Y => DVec3::Y,
            Axis::Z => DVec3::Z,
        }
    }

    /// Active right-hand rotation about the axis by `angle` radians ([`rot_x`], [`rot_y`] or
    /// [`rot_z`]).
    pub fn rotation(self, angle: f64) -> DMat3 {
        match self {
            Axis::X => rot_x(angle),
            Axis::Y => rot_y(angle),
            Axis::Z => rot_z(angle),
        }
    }

    /// The unit quaternion of [`rotation`](Self::rotation): `(sin(angle/2)·axis, cos(angle/2))`.
    pub fn quat(self, angle: f64) -> DQuat {
        match self {
            Axis::X => DQuat::from_rotation_x(angle),
            Axis::Y => DQuat::from_rotation_y(angle),
            Axis::Z => DQuat::from_rotation_z(angle),
        }
    }
}

impl fmt::Display for Axis {
    /// `x`, `y` or `z`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.name())
    }
}

/// One of the twelve orders of three rotations about coordinate axes, no two neighbours equal.
///
/// Six are proper Euler sequences (the first axis repeated last) and six are Tait–Bryan (three
/// different axes), listed in [`ALL`](Self::ALL) in the order of the seed lecture. The variant
/// names the axes in the order the angles are given; whether those axes turn with the body is
/// the [`Frame`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sequence {
    /// Proper Euler z-x-z.
    ZXZ,
    /// Proper Euler x-y-x.
    XYX,
    /// Proper Euler y-z-y.
    YZY,
    /// Proper Euler z-y-z.
    ZYZ,
    /// Proper Euler x-z-x.
    XZX,
    /// Proper Euler y-x-y.
    YXY,
    /// Tait–Bryan x-y-z.
    XYZ,
    /// Tait–Bryan y-z-x.
    YZX,
    /// Tait–Bryan z-x-y.
    ZXY,
    /// Tait–Bryan x-z-y.
    XZY,
    /// Tait–Bryan z-y-x: yaw, pitch, roll (the viewer's [`EulerZyx`](super::EulerZyx)).
    ZYX,
    /// Tait–Bryan y-x-z.
    YXZ,
}

impl Sequence {
    /// The twelve, in the seed lecture's order: proper Euler z-x-z, x-y-x, y-z-y, z-y-z, x-z-x,
    /// y-x-y; Tait–Bryan x-y-z, y-z-x, z-x-y, x-z-y, z-y-x, y-x-z.
    pub const ALL: [Sequence; 12] = [
        Sequence::ZXZ,
        Sequence::XYX,
        Sequence::YZY,
        Sequence::ZYZ,
        Sequence::XZX,
        Sequence::YXY,
        Sequence::XYZ,
        Sequence::YZX,
        Sequence::ZXY,
        Sequence::XZY,
        Sequence::ZYX,
        Sequence::YXZ,
    ];

    /// The three axes, in the order the angles are given.
    pub const fn axes(self) -> [Axis; 3] {
        use Axis::{X, Y, Z};
        match self {
            Sequence::ZXZ => [Z, X, Z],
            Sequence::XYX => [X, Y, X],
            Sequence::YZY => [Y, Z, Y],
            Sequence::ZYZ => [Z, Y, Z],
            Sequence::XZX => [X, Z, X],
            Sequence::YXY => [Y, X, Y],
            Sequence::XYZ => [X, Y, Z],
            Sequence::YZX => [Y, Z, X],
            Sequence::ZXY => [Z, X, Y],
            Sequence::XZY => [X, Z, Y],
            Sequence::ZYX => [Z, Y, X],
            Sequence::YXZ => [Y, X, Z],
        }
    }

    /// The sequence with these axes; `None` when two neighbours are equal (e.g. x-x-y), which
    /// is not a valid sequence.
    pub fn from_axes(axes: [Axis; 3]) -> Option<Sequence> {
        Sequence::ALL.into_iter().find(|s| s.axes() == axes)
    }

    /// True for the six proper Euler sequences (first axis = third axis).
    pub const fn is_proper_euler(self) -> bool {
        let [a, _, c] = self.axes();
        a as usize == c as usize
    }

    /// True for the six Tait–Bryan sequences (three different axes).
    pub const fn is_tait_bryan(self) -> bool {
        !self.is_proper_euler()
    }

    /// The axes in the opposite order (z-y-x → x-y-z; a proper Euler sequence is its own
    /// reverse).
    pub fn reversed(self) -> Sequence {
        let [a, b, c] = self.axes();
        match Sequence::from_axes([c, b, a]) {
            Some(s) => s,
            None => unreachable!("the reverse of a valid sequence is valid"),
        }
    }

    /// The parity ε: `+1.0` when the second axis follows the first in the cycle x → y → z → x
    /// (x-y-z, y-z-x, z-x-y, x-y-x, y-z-y, z-x-z), `−1.0` otherwise. It is the sign in the
    /// matrix, its inverse and the gimbal-lock rule (module docs).
    pub const fn parity(self) -> f64 {
        let [a, b, _] = self.axes();
        if (a as usize + 1) % 3 == b as usize {
            1.0
        } else {
            -1.0
        }
    }

    /// The documented range of the middle angle β, in radians: `[−π/2, π/2]` for Tait–Bryan,
    /// `[0, π]` for proper Euler. Gimbal lock is at either end.
    pub const fn middle_range(self) -> (f64, f64) {
        if self.is_proper_euler() {
            (0.0, PI)
        } else {
            (-FRAC_PI_2, FRAC_PI_2)
        }
    }
}

impl fmt::Display for Sequence {
    /// `zyx`; the alternate form `{:#}` writes `z-y-x`, as in the seed lecture.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c] = self.axes();
        if f.alternate() {
            write!(f, "{a}-{b}-{c}")
        } else {
            write!(f, "{a}{b}{c}")
        }
    }
}

/// Why a [`Sequence`], [`Frame`] or [`Convention`] could not be parsed.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ParseConventionError {
    /// Not three axis letters, or two neighbours equal.
    #[error(
        "`{0}` is not a rotation sequence: expected three axes from x, y, z with no two \
         neighbours equal, e.g. zyx, z-y-x or ZXZ"
    )]
    Sequence(String),
    /// The part after the comma is not a frame.
    #[error("`{0}` is not a frame: expected intrinsic or extrinsic")]
    Frame(String),
}

impl FromStr for Sequence {
    type Err = ParseConventionError;

    /// Three axis letters in either case, optionally separated by `-`: `zyx`, `z-y-x`, `ZYX`.
    /// Surrounding white space is ignored.
    ///
    /// # Errors
    ///
    /// [`ParseConventionError::Sequence`] for anything else, including x-x-y.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let err = || ParseConventionError::Sequence(s.to_string());
        let t = s.trim();
        let letters: Vec<char> = if t.contains('-') {
            let parts: Vec<&str> = t.split('-').collect();
            if parts.iter().any(|p| p.chars().count() != 1) {
                return Err(err());
            }
            parts.iter().filter_map(|p| p.chars().next()).collect()
        } else {
            t.chars().collect()
        };
        let axes: Vec<Axis> = letters
            .into_iter()
            .map(Axis::from_char)
            .collect::<Option<_>>()
            .ok_or_else(err)?;
        let axes: [Axis; 3] = axes.try_into().map_err(|_| err())?;
        Sequence::from_axes(axes).ok_or_else(err)
    }
}

/// Whether the axes of a sequence turn with the body or stay fixed in the world.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Frame {
    /// Rotating axes: for a-b-c, turn α about a, then β about the turned b′, then γ about the
    /// twice-turned c″: `R = R_a(α)·R_b(β)·R_c(γ)`.
    #[default]
    Intrinsic,
    /// Fixed axes: for a-b-c, turn α about the fixed a, then β about the fixed b, then γ about
    /// the fixed c: `R = R_c(γ)·R_b(β)·R_a(α)`.
    Extrinsic,
}

impl Frame {
    /// `"intrinsic"` or `"extrinsic"`.
    pub const fn name(self) -> &'static str {
        match self {
            Frame::Intrinsic => "intrinsic",
            Frame::Extrinsic => "extrinsic",
        }
    }

    /// The other frame.
    pub const fn other(self) -> Frame {
        match self {
            Frame::Intrinsic => Frame::Extrinsic,
            Frame::Extrinsic => Frame::Intrinsic,
        }
    }
}

impl fmt::Display for Frame {
    /// `intrinsic` or `extrinsic`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Frame {
    type Err = ParseConventionError;

    /// `intrinsic` or `extrinsic`, either case, surrounding white space ignored.
    ///
    /// # Errors
    ///
    /// [`ParseConventionError::Frame`] for anything else.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "intrinsic" => Ok(Frame::Intrinsic),
            "extrinsic" => Ok(Frame::Extrinsic),
            _ => Err(ParseConventionError::Frame(s.to_string())),
        }
    }
}

/// An Euler-angle convention: the order of the axes and whether they rotate with the body.
///
/// Angles given in a convention are in radians, in the order of its [`Sequence`]'s axes, and
/// build the active body → world rotation (module docs). There are 24: [`ALL`](Self::ALL).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Convention {
    /// The axes, in the order the angles are given.
    pub sequence: Sequence,
    /// Whether those axes turn with the body (intrinsic) or stay fixed (extrinsic).
    pub frame: Frame,
}

impl Convention {
    /// The viewer's attitude convention: intrinsic z-y-x (yaw, pitch, roll), as
    /// [`EulerZyx`](super::EulerZyx).
    pub const VIEWER: Convention = Convention::intrinsic(Sequence::ZYX);

    /// All 24: the twelve sequences intrinsic, then the twelve extrinsic.
    pub const ALL: [Convention; 24] = {
        let mut all = [Convention::VIEWER; 24];
        let mut i = 0;
        while i < 12 {
            all[i] = Convention::intrinsic(Sequence::ALL[i]);
            all[i + 12] = Convention::extrinsic(Sequence::ALL[i]);
            i += 1;
        }
        all
    };

    /// The convention with these axes and frame.
    pub const fn new(sequence: Sequence, frame: Frame) -> Self {
        Self { sequence, frame }
    }

    /// `sequence` about rotating axes.
    pub const fn intrinsic(sequence: Sequence) -> Self {
        Self::new(sequence, Frame::Intrinsic)
    }

    /// `sequence` about fixed axes.
    pub const fn extrinsic(sequence: Sequence) -> Self {
        Self::new(sequence, Frame::Extrinsic)
    }

    /// The convention that gives the same rotation with the three angles in reverse order:
    /// intrinsic a-b-c ↔ extrinsic c-b-a.
    pub fn other_frame(self) -> Self {
        Self::new(self.sequence.reversed(), self.frame.other())
    }

    /// The same convention read about rotating axes: `self` if intrinsic, else
    /// [`other_frame`](Self::other_frame) (whose angles are this one's reversed).
    pub fn as_intrinsic(self) -> Self {
        match self.frame {
            Frame::Intrinsic => self,
            Frame::Extrinsic => self.other_frame(),
        }
    }

    /// glam's name for the same convention: intrinsic `zyx` is `EulerRot::ZYX`, extrinsic `zyx`
    /// is `EulerRot::ZYXEx`, with the angles passed in the same order.
    pub const fn to_glam(self) -> EulerRot {
        use EulerRot as G;
        use Sequence as S;
        match (self.frame, self.sequence) {
            (Frame::Intrinsic, S::ZXZ) => G::ZXZ,
            (Frame::Intrinsic, S::XYX) => G::XYX,
            (Frame::Intrinsic, S::YZY) => G::YZY,
            (Frame::Intrinsic, S::ZYZ) => G::ZYZ,
            (Frame::Intrinsic, S::XZX) => G::XZX,
            (Frame::Intrinsic, S::YXY) => G::YXY,
            (Frame::Intrinsic, S::XYZ) => G::XYZ,
            (Frame::Intrinsic, S::YZX) => G::YZX,
            (Frame::Intrinsic, S::ZXY) => G::ZXY,
            (Frame::Intrinsic, S::XZY) => G::XZY,
            (Frame::Intrinsic, S::ZYX) => G::ZYX,
            (Frame::Intrinsic, S::YXZ) => G::YXZ,
            (Frame::Extrinsic, S::ZXZ) => G::ZXZEx,
            (Frame::Extrinsic, S::XYX) => G::XYXEx,
            (Frame::Extrinsic, S::YZY) => G::YZYEx,
            (Frame::Extrinsic, S::ZYZ) => G::ZYZEx,
            (Frame::Extrinsic, S::XZX) => G::XZXEx,
            (Frame::Extrinsic, S::YXY) => G::YXYEx,
            (Frame::Extrinsic, S::XYZ) => G::XYZEx,
            (Frame::Extrinsic, S::YZX) => G::YZXEx,
            (Frame::Extrinsic, S::ZXY) => G::ZXYEx,
            (Frame::Extrinsic, S::XZY) => G::XZYEx,
            (Frame::Extrinsic, S::ZYX) => G::ZYXEx,
            (Frame::Extrinsic, S::YXZ) => G::YXZEx,
        }
    }

    /// The convention glam calls `rot` (inverse of [`to_glam`](Self::to_glam)).
    pub fn from_glam(rot: EulerRot) -> Self {
        match Convention::ALL.into_iter().find(|c| c.to_glam() == rot) {
            Some(c) => c,
            None => unreachable!("every EulerRot has a convention"),
        }
    }
}

impl Default for Convention {
    /// [`Convention::VIEWER`]: intrinsic z-y-x.
    fn default() -> Self {
        Convention::VIEWER
    }
}

impl fmt::Display for Convention {
    /// `zyx` for intrinsic, `zyx,extrinsic` for extrinsic (`{:#}`: `z-y-x,extrinsic`); parses
    /// back with [`FromStr`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.sequence, f)?;
        match self.frame {
            Frame::Intrinsic => Ok(()),
            Frame::Extrinsic => write!(f, ",{}", self.frame),
        }
    }
}

impl FromStr for Convention {
    type Err = ParseConventionError;

    /// A [`Sequence`] (`zyx`, `z-y-x`, `ZYX`), optionally followed by `,intrinsic` or
    /// `,extrinsic`; without a frame it is intrinsic. White space around the parts is ignored.
    ///
    /// # Errors
    ///
    /// [`ParseConventionError`] naming the part that is wrong.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (seq, frame) = match s.split_once(',') {
            Some((seq, frame)) => (seq, frame.parse()?),
            None => (s, Frame::Intrinsic),
        };
        Ok(Convention::new(seq.parse()?, frame))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_spellings_and_prints_back() {
        for text in ["zyx", "z-y-x", "ZYX", " Z-y-X "] {
            assert_eq!(text.parse::<Sequence>(), Ok(Sequence::ZYX), "{text:?}");
        }
        assert_eq!(
            "zxz, Extrinsic".parse::<Convention>(),
            Ok(Convention::extrinsic(Sequence::ZXZ))
        );
        assert_eq!(
            "x-y-z,intrinsic".parse::<Convention>(),
            Ok(Convention::intrinsic(Sequence::XYZ))
        );
        for c in Convention::ALL {
            assert_eq!(c.to_string().parse::<Convention>(), Ok(c));
            assert_eq!(format!("{c:#}").parse::<Convention>(), Ok(c));
        }
        assert_eq!(Convention::VIEWER.to_string(), "zyx");
        assert_eq!(
            format!("{:#}", Convention::extrinsic(Sequence::ZYX)),
            "z-y-x,extrinsic"
        );
    }

    #[test]
    fn rejects_what_is_not_a_sequence() {
        for text in [
            "", "zy", "zyxz", "zzx", "xyy", "abc", "z--y-x", "zy-x", "z-y-x-",
        ] {
            assert_eq!(
                text.parse::<Sequence>(),
                Err(ParseConventionError::Sequence(text.to_string())),
                "{text:?}"
            );
        }
        assert_eq!(
            "zyx,sideways".parse::<Convention>(),
            Err(ParseConventionError::Frame("sideways".to_string()))
        );
    }

    #[test]
    fn twelve_sequences_six_of_each_kind() {
        let proper = Sequence::ALL.iter().filter(|s| s.is_proper_euler()).count();
        assert_eq!(proper, 6);
        for s in Sequence::ALL {
            assert_eq!(Sequence::from_axes(s.axes()), Some(s));
            assert_eq!(s.reversed().reversed(), s);
        }
        assert_eq!(Sequence::from_axes([Axis::X, Axis::X, Axis::Y]), None);
        let all: std::collections::HashSet<_> = Convention::ALL.into_iter().collect();
        assert_eq!(all.len(), 24);
    }
}
