//! Typed indices where two index spaces of the plan meet: moving bodies (`Plan::bodies`, and
//! the per-body vectors of the workspace), tree joints (`Plan::joints`) and scene objects
//! (`Plan::objects`, the same order as `ValidScene::objects`). A `usize` of one space cannot be
//! passed where another is meant. Plain data; touches nothing.

macro_rules! typed_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub usize);

        impl $name {
            /// The plain index.
            #[inline]
            pub fn index(self) -> usize {
                self.0
            }
        }
    };
}

typed_id!(
    /// A moving body: index into `Plan::bodies` and the workspace's per-body vectors.
    BodyId
);
typed_id!(
    /// A tree joint: index into `Plan::joints` (Fix joints are merged away, so this is not
    /// the index of the joint in the scene).
    JointId
);
typed_id!(
    /// A scene object: index into `Plan::objects` and `ValidScene::objects`.
    ObjectId
);

/// A vector indexed by the typed id `I` (and by position, as any vector):
/// `plan.bodies[body_id]` compiles, `plan.bodies[object_id]` does not.
#[derive(Clone, Debug, PartialEq)]
pub struct IdVec<I, T> {
    items: Vec<T>,
    id: std::marker::PhantomData<fn(I)>,
}

impl<I, T> IdVec<I, T> {
    /// An empty vector.
    pub fn new() -> Self {
        Self::from(vec![])
    }
}

impl<I, T> Default for IdVec<I, T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<I, T> From<Vec<T>> for IdVec<I, T> {
    fn from(items: Vec<T>) -> Self {
        IdVec {
            items,
            id: std::marker::PhantomData,
        }
    }
}

impl<I, T> std::ops::Deref for IdVec<I, T> {
    type Target = Vec<T>;
    #[inline]
    fn deref(&self) -> &Vec<T> {
        &self.items
    }
}

impl<I, T> std::ops::DerefMut for IdVec<I, T> {
    #[inline]
    fn deref_mut(&mut self) -> &mut Vec<T> {
        &mut self.items
    }
}

macro_rules! id_index {
    ($($name:ident),*) => {$(
        impl<T> IdVec<$name, T> {
            /// The item of id `i`, `None` if out of range.
            #[inline]
            pub fn get(&self, i: $name) -> Option<&T> {
                self.items.get(i.0)
            }
            /// The ids in order with their items.
            pub fn iter_ids(&self) -> impl Iterator<Item = ($name, &T)> + '_ {
                self.items.iter().enumerate().map(|(i, t)| ($name(i), t))
            }
        }
        impl<T> std::ops::Index<$name> for IdVec<$name, T> {
            type Output = T;
            #[inline]
            fn index(&self, i: $name) -> &T {
                &self.items[i.0]
            }
        }
        impl<T> std::ops::IndexMut<$name> for IdVec<$name, T> {
            #[inline]
            fn index_mut(&mut self, i: $name) -> &mut T {
                &mut self.items[i.0]
            }
        }
    )*};
}
id_index!(BodyId, JointId, ObjectId);

// By position too (loops over `iter().enumerate()`); a different id type does not compile.
impl<I, T> std::ops::Index<usize> for IdVec<I, T> {
    type Output = T;
    #[inline]
    fn index(&self, i: usize) -> &T {
        &self.items[i]
    }
}
impl<I, T> std::ops::IndexMut<usize> for IdVec<I, T> {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut T {
        &mut self.items[i]
    }
}

impl<'a, I, T> IntoIterator for &'a IdVec<I, T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.iter()
    }
}
