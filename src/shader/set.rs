//! Several fragment shaders in one scene, chosen per draw.
//!
//! A scene holds a [`ShaderSet`]: one shader (`&S`, from
//! [`Scene::shader`](crate::scene::Scene::shader)), a tuple of up to eight
//! (from [`Scene::shaders`](crate::scene::Scene::shaders)), or
//! [`NoShader`]. A [`Shading::Shader`](crate::scene::Shading::Shader) draw
//! names its shader by its place in the set
//! ([`Draw::shader`](crate::scene::Draw::shader), 0 by default).
//!
//! The renderer is monomorphized for every shader of the set: picking one
//! is a `match` on the index per triangle, never a `dyn` call, and each
//! shader's span loop is its own. The set hands its shader to the renderer
//! through a [`VisitShader`], a function generic over the shader's type.
//!
//! ```
//! use embedded_graphics::pixelcolor::Rgb565;
//! use microraster::prelude::*;
//! use microraster::shader::{Normals, ShaderSet};
//!
//! let camera = Camera::new(Mat4::IDENTITY, Mat4::IDENTITY);
//! let scene = Scene::new(camera, &[]).shaders((Textured, Normals));
//! assert_eq!(<(Textured, Normals) as ShaderSet<Rgb565>>::LEN, 2);
//! # let _ = scene;
//! ```

use super::{FragmentShader, ShaderError};
use crate::scene::{Draw, NoShader};

/// Something generic over a fragment shader's type, which a
/// [`ShaderSet`] calls with the shader a draw picked. The renderer
/// implements it: a program only names it to implement nothing.
pub trait VisitShader<C> {
    /// What the visit returns.
    type Output;
    /// Called with the picked shader.
    fn visit<S: FragmentShader<C>>(self, shader: &S) -> Self::Output;
}

/// The fragment shaders of a scene: `&S` for one shader, a tuple of up to
/// eight shaders (by value or by reference), or [`NoShader`].
pub trait ShaderSet<C>: private::Sealed {
    /// How many shaders the set holds.
    const LEN: usize;

    /// Calls `v` with shader `index` of the set, or returns `None` when
    /// the set has fewer shaders.
    fn visit<V: VisitShader<C>>(&self, index: usize, v: V) -> Option<V::Output>;
}

/// [`FragmentShader::check`] of shader `index` for `draw`, or `None` when
/// the set has no such shader.
pub(crate) fn check<C, S: ShaderSet<C>>(
    set: &S,
    index: usize,
    draw: &Draw<'_>,
) -> Option<Result<(), ShaderError>> {
    struct Check<'d, 'a>(&'d Draw<'a>);
    impl<C> VisitShader<C> for Check<'_, '_> {
        type Output = Result<(), ShaderError>;
        fn visit<S: FragmentShader<C>>(self, shader: &S) -> Self::Output {
            shader.check(self.0)
        }
    }
    set.visit(index, Check(draw))
}

mod private {
    pub trait Sealed {}
}

impl private::Sealed for NoShader {}

/// No shader at all: every [`Shading::Shader`](crate::scene::Shading::Shader)
/// draw is an error, and no fragment-shader code is linked.
impl<C> ShaderSet<C> for NoShader {
    const LEN: usize = 0;
    #[inline(always)]
    fn visit<V: VisitShader<C>>(&self, _: usize, _: V) -> Option<V::Output> {
        None
    }
}

impl<S: ?Sized> private::Sealed for &S {}

/// One shader, as [`Scene::shader`](crate::scene::Scene::shader) sets it.
impl<C, S: FragmentShader<C>> ShaderSet<C> for &S {
    const LEN: usize = 1;
    #[inline(always)]
    fn visit<V: VisitShader<C>>(&self, index: usize, v: V) -> Option<V::Output> {
        match index {
            0 => Some(v.visit(*self)),
            _ => None,
        }
    }
}

/// Implements [`ShaderSet`] for a tuple: `$t` its types, `$i` their indices.
macro_rules! tuple_set {
    ($len:expr; $($t:ident $i:tt),+) => {
        impl<$($t),+> private::Sealed for ($($t,)+) {}

        /// Shaders picked by their place in the tuple.
        impl<C, $($t: FragmentShader<C>),+> ShaderSet<C> for ($($t,)+) {
            const LEN: usize = $len;
            #[inline(always)]
            fn visit<V: VisitShader<C>>(&self, index: usize, v: V) -> Option<V::Output> {
                match index {
                    $($i => Some(v.visit(&self.$i)),)+
                    _ => None,
                }
            }
        }
    };
}

tuple_set!(1; A 0);
tuple_set!(2; A 0, B 1);
tuple_set!(3; A 0, B 1, D 2);
tuple_set!(4; A 0, B 1, D 2, E 3);
tuple_set!(5; A 0, B 1, D 2, E 3, G 4);
tuple_set!(6; A 0, B 1, D 2, E 3, G 4, H 5);
tuple_set!(7; A 0, B 1, D 2, E 3, G 4, H 5, I 6);
tuple_set!(8; A 0, B 1, D 2, E 3, G 4, H 5, I 6, J 7);
