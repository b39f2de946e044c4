//! The macro the flat layout is declared with ([`super::layout`]): one line per field gives its
//! Rust constant (offset from the previous fields' sizes), its JavaScript name and its row of
//! the layout table ([`Row`]), from which `LAYOUT`, the TypeScript type and the reference
//! table are made.

/// One named offset of the layout: its JavaScript path (`output.side.contactPush`) and its
/// offset (absolute for top-level fields, within its slot for a slot's fields; a stride row
/// holds the stride), with what the generated files say of it ([`Detail`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Row {
    /// Dotted JavaScript path, as `LAYOUT` nests it.
    pub path: &'static str,
    /// Index into the input or output array (a slot's fields: within the slot; a stride row:
    /// the stride).
    pub offset: usize,
    /// Size, kind and description.
    pub detail: Detail,
}

/// What kind of row a [`Row`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowKind {
    /// Floats of the frame.
    Field,
    /// Distance between consecutive slots of the field before it (`input.handStride`).
    Stride,
    /// A field inside each slot of the last strided field (`input.hand.world`).
    SlotField,
    /// The array's length.
    Length,
}

/// A row's size (`count` repeats of `width` floats), kind and description: for the generated
/// TypeScript type and reference table, so native builds only. In the `.wasm` it is empty,
/// which keeps the descriptions out of it (the size budget; `LAYOUT` needs paths and offsets).
#[cfg(not(target_arch = "wasm32"))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Detail {
    /// Repeats (1 for a single value or vector).
    pub count: usize,
    /// Floats per repeat.
    pub width: usize,
    /// What kind of row this is.
    pub kind: RowKind,
    /// What the field holds (the Rust doc comment).
    pub doc: &'static str,
}

/// Empty in the `.wasm` (see the native [`Detail`]).
#[cfg(target_arch = "wasm32")]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Detail;

impl Detail {
    /// A row's detail (in the `.wasm`: nothing).
    #[must_use]
    #[allow(unused_variables)]
    pub const fn new(count: usize, width: usize, kind: RowKind, doc: &'static str) -> Self {
        #[cfg(not(target_arch = "wasm32"))]
        return Detail {
            count,
            width,
            kind,
            doc,
        };
        #[cfg(target_arch = "wasm32")]
        return Detail;
    }
}

/// Declares one side of the layout (`input` or `output`): a module of offset constants, each
/// one the sum of the sizes before it, and `ROWS`, the layout table of that side.
///
/// ```text
/// layout_side! { input "input" {
///     /// doc
///     HAND_COUNT handCount: 1;
///     /// doc
///     POSE pose: [POSE_LANDMARKS] stride POSE_STRIDE poseStride = 4;
///     /// doc
///     HANDS hands: [MAX_HANDS] stride HAND_STRIDE handStride = 132, slot hand "hand" {
///         /// doc
///         SCORE score: 1;
///     };
/// } }
/// ```
macro_rules! layout_side {
    (
        $(#[doc = $mdoc:literal])*
        $side:ident $sjs:literal { $($body:tt)* }
    ) => {
        $(#[doc = $mdoc])*
        pub mod $side {
            #[allow(unused_imports)]
            use super::*;
            layout_side!(@consts (0usize) $($body)*);
            /// The rows of this side's layout table, in memory order (the length last).
            pub const ROWS: &[$crate::flat::declare::Row] = &layout_side!(@rows $sjs [] $($body)*);
        }
    };

    // ---- one row.
    (@row $kind:ident, $path:expr, $offset:expr, $count:expr, $width:expr, $doc:expr) => {
        $crate::flat::declare::Row {
            path: $path,
            offset: $offset,
            detail: $crate::flat::declare::Detail::new(
                $count,
                $width,
                $crate::flat::declare::RowKind::$kind,
                $doc,
            ),
        }
    };

    // ---- constants: each field's offset is the previous offset plus the previous size.
    (@consts ($off:expr)) => {
        /// Length of the array.
        pub const LEN: usize = $off;
    };
    (@consts ($off:expr)
        $(#[doc = $d:literal])* $name:ident $js:ident : [$count:expr] stride $sname:ident $sjs:ident = $stride:expr, slot $slot:ident $slotjs:literal { $($inner:tt)* };
        $($rest:tt)*
    ) => {
        $(#[doc = $d])*
        pub const $name: usize = $off;
        /// Floats per slot of the field above.
        pub const $sname: usize = $stride;
        /// Offsets inside one slot.
        pub mod $slot {
            #[allow(unused_imports)]
            use super::*;
            layout_side!(@slot (0usize) $($inner)*);
        }
        const _: () = assert!($slot::SIZE <= $sname, "a slot's fields overflow its stride");
        layout_side!(@consts ($name + ($count) * $sname) $($rest)*);
    };
    (@consts ($off:expr)
        $(#[doc = $d:literal])* $name:ident $js:ident : [$count:expr] stride $sname:ident $sjs:ident = $stride:expr;
        $($rest:tt)*
    ) => {
        $(#[doc = $d])*
        pub const $name: usize = $off;
        /// Floats per entry of the field above.
        pub const $sname: usize = $stride;
        layout_side!(@consts ($name + ($count) * $sname) $($rest)*);
    };
    (@consts ($off:expr)
        $(#[doc = $d:literal])* $name:ident $js:ident : [$count:expr] x $width:expr;
        $($rest:tt)*
    ) => {
        $(#[doc = $d])*
        pub const $name: usize = $off;
        layout_side!(@consts ($name + ($count) * ($width)) $($rest)*);
    };
    (@consts ($off:expr)
        $(#[doc = $d:literal])* $name:ident $js:ident : $size:expr;
        $($rest:tt)*
    ) => {
        $(#[doc = $d])*
        pub const $name: usize = $off;
        layout_side!(@consts ($name + ($size)) $($rest)*);
    };

    // ---- a slot's constants, and its used size.
    (@slot ($off:expr)) => {
        /// Floats used of a slot (the stride may leave room to grow).
        pub const SIZE: usize = $off;
    };
    (@slot ($off:expr)
        $(#[doc = $d:literal])* $name:ident $js:ident : [$count:expr] x $width:expr;
        $($rest:tt)*
    ) => {
        $(#[doc = $d])*
        pub const $name: usize = $off;
        layout_side!(@slot ($name + ($count) * ($width)) $($rest)*);
    };
    (@slot ($off:expr)
        $(#[doc = $d:literal])* $name:ident $js:ident : $size:expr;
        $($rest:tt)*
    ) => {
        $(#[doc = $d])*
        pub const $name: usize = $off;
        layout_side!(@slot ($name + ($size)) $($rest)*);
    };

    // ---- a slot's rows (then back to the side's own fields).
    (@rows $sjs:literal [$($acc:expr,)*] @slotrows $sjs2:literal $slotjs:literal $slot:ident [] $($rest:tt)*) => {
        layout_side!(@rows $sjs [$($acc,)*] $($rest)*)
    };
    (@rows $sjs:literal [$($acc:expr,)*] @slotrows $sjs2:literal $slotjs:literal $slot:ident [
        $(#[doc = $d:literal])* $name:ident $js:ident : [$count:expr] x $width:expr;
        $($inner:tt)*
    ] $($rest:tt)*) => {
        layout_side!(@rows $sjs [$($acc,)*
            layout_side!(@row SlotField, concat!($sjs, ".", $slotjs, ".", stringify!($js)), $slot::$name, $count, $width, concat!($($d),*)),
        ] @slotrows $sjs2 $slotjs $slot [$($inner)*] $($rest)*)
    };
    (@rows $sjs:literal [$($acc:expr,)*] @slotrows $sjs2:literal $slotjs:literal $slot:ident [
        $(#[doc = $d:literal])* $name:ident $js:ident : $size:expr;
        $($inner:tt)*
    ] $($rest:tt)*) => {
        layout_side!(@rows $sjs [$($acc,)*
            layout_side!(@row SlotField, concat!($sjs, ".", $slotjs, ".", stringify!($js)), $slot::$name, 1, $size, concat!($($d),*)),
        ] @slotrows $sjs2 $slotjs $slot [$($inner)*] $($rest)*)
    };

    // ---- rows, accumulated in memory order.
    (@rows $sjs:literal [$($acc:expr,)*]) => {
        [$($acc,)* layout_side!(@row Length, concat!($sjs, ".length"), LEN, 0, 0, "")]
    };
    (@rows $sjs:literal [$($acc:expr,)*]
        $(#[doc = $d:literal])* $name:ident $js:ident : [$count:expr] stride $sname:ident $sjsn:ident = $stride:expr, slot $slot:ident $slotjs:literal { $($inner:tt)* };
        $($rest:tt)*
    ) => {
        layout_side!(@rows $sjs [$($acc,)*
            layout_side!(@row Field, concat!($sjs, ".", stringify!($js)), $name, $count, $sname, concat!($($d),*)),
            layout_side!(@row Stride, concat!($sjs, ".", stringify!($sjsn)), $sname, 1, 1, ""),
            ] @slotrows $sjs $slotjs $slot [$($inner)*] $($rest)*)
    };
    (@rows $sjs:literal [$($acc:expr,)*]
        $(#[doc = $d:literal])* $name:ident $js:ident : [$count:expr] stride $sname:ident $sjsn:ident = $stride:expr;
        $($rest:tt)*
    ) => {
        layout_side!(@rows $sjs [$($acc,)*
            layout_side!(@row Field, concat!($sjs, ".", stringify!($js)), $name, $count, $sname, concat!($($d),*)),
            layout_side!(@row Stride, concat!($sjs, ".", stringify!($sjsn)), $sname, 1, 1, ""),
        ] $($rest)*)
    };
    (@rows $sjs:literal [$($acc:expr,)*]
        $(#[doc = $d:literal])* $name:ident $js:ident : [$count:expr] x $width:expr;
        $($rest:tt)*
    ) => {
        layout_side!(@rows $sjs [$($acc,)*
            layout_side!(@row Field, concat!($sjs, ".", stringify!($js)), $name, $count, $width, concat!($($d),*)),
        ] $($rest)*)
    };
    (@rows $sjs:literal [$($acc:expr,)*]
        $(#[doc = $d:literal])* $name:ident $js:ident : $size:expr;
        $($rest:tt)*
    ) => {
        layout_side!(@rows $sjs [$($acc,)*
            layout_side!(@row Field, concat!($sjs, ".", stringify!($js)), $name, 1, $size, concat!($($d),*)),
        ] $($rest)*)
    };

}

pub(crate) use layout_side;
