//! The helm's outgoing buffers: the postings of one iteration (reused across iterations,
//! names shared) and pHelmIvP's duplicate-post filter.

use super::*;

/// The postings of one iteration. The `Posting`s of earlier iterations are kept and
/// overwritten in place, so a steady-state iteration reuses their value strings; variable
/// names and aux fields are shared [`ByteString`]s ([`Names`]), so the app that publishes the
/// postings copies only their string values.
#[derive(Default)]
pub(super) struct Outbox {
    pub(super) posts: Vec<Posting>,
    pub(super) len: usize,
    pub(super) names: Names,
    /// Where [`Outbox::text`] writes.
    pub(super) scratch: String,
}

/// Most names [`Names`] keeps before it starts afresh.
pub(super) const NAMES_LIMIT: usize = 4096;

/// One shared copy of each name the helm posts under (variables, aux fields such as a
/// behaviour's name): posting a name is a reference count, not a copy.
#[derive(Default)]
pub(super) struct Names {
    pub(super) set: FxHashSet<ByteString>,
}

impl Names {
    pub(super) fn get(&mut self, s: &str) -> ByteString {
        if s.is_empty() {
            return ByteString::new();
        }
        if let Some(n) = self.set.get(s) {
            return n.clone();
        }
        if self.set.len() >= NAMES_LIMIT {
            self.set.clear();
        }
        let n = ByteString::from(s);
        // The first clone makes the buffer a shared one; later clones only count references.
        let shared = n.clone();
        self.set.insert(n);
        shared
    }
}

impl Outbox {
    pub(super) fn clear(&mut self) {
        self.len = 0;
    }
    pub(super) fn as_slice(&self) -> &[Posting] {
        &self.posts[..self.len]
    }
    /// The next posting, with `var` and an empty `aux` (the caller sets value and aux).
    pub(super) fn next(&mut self, var: &str) -> &mut Posting {
        let key = self.names.get(var);
        self.next_key(key)
    }
    /// The next posting under the name `key`, made once by the caller ([`Names::get`] or
    /// [`ByteString::from_static`]: no lookup here), with an empty `aux`.
    pub(super) fn next_key(&mut self, key: ByteString) -> &mut Posting {
        if self.len == self.posts.len() {
            self.posts.push(Posting::double(ByteString::new(), 0.0));
        }
        let p = &mut self.posts[self.len];
        self.len += 1;
        p.key = key;
        p.aux = ByteString::new();
        p
    }
    /// The next posting, with `var` and the shared `aux`.
    pub(super) fn next_with_aux(&mut self, var: &str, aux: &str) -> &mut Posting {
        let aux = self.names.get(aux);
        let p = self.next(var);
        p.aux = aux;
        p
    }
    pub(super) fn push(&mut self, var: &str, value: Value, aux: &str) {
        let p = self.next_with_aux(var, aux);
        p.value = value;
    }
    /// [`Outbox::push`] under a name known at compile time, with an empty aux: the name is
    /// a static [`ByteString`], neither hashed nor counted.
    pub(super) fn push_static(&mut self, var: &'static str, value: Value) {
        let p = self.next_key(ByteString::from_static(var));
        p.value = value;
    }
    /// Posts a string value that `write` writes into a cleared, reused buffer; the text is
    /// copied into a shared string unless the posting in this place last iteration had the
    /// same text, which is then shared again (a steady `IVPHELM_STATE = DRIVE` costs nothing).
    pub(super) fn text(&mut self, var: &'static str, write: impl FnOnce(&mut String)) {
        let mut buf = std::mem::take(&mut self.scratch);
        buf.clear();
        write(&mut buf);
        let p = self.next_key(ByteString::from_static(var));
        if !matches!(&p.value, Value::String(old) if *old == *buf) {
            p.value = Value::String(ByteString::from(buf.as_str()));
        }
        self.scratch = buf;
    }
    /// Posts a copy of `text`.
    pub(super) fn text_copy(&mut self, var: &'static str, text: &str) {
        self.text(var, |s| s.push_str(text));
    }
}

/// pHelmIvP's duplicate-post filter: the last value posted under each key.
#[derive(Default)]
pub(super) struct DupFilter {
    pub(super) text: FxHashMap<String, ByteString>,
    pub(super) num: FxHashMap<String, f64>,
}

impl DupFilter {
    /// Whether a posting under `key` is new (updates the filter when it is).
    pub(super) fn changed(&mut self, key: &str, value: &Value) -> bool {
        match value {
            Value::String(s) => match self.text.get_mut(key) {
                Some(old) if *old == *s => false,
                Some(old) => {
                    old.clone_from(s);
                    true
                }
                None => {
                    self.text.insert(key.to_string(), s.clone());
                    true
                }
            },
            Value::Double(x) => match self.num.get_mut(key) {
                Some(old) if *old == *x => false,
                Some(old) => {
                    *old = *x;
                    true
                }
                None => {
                    self.num.insert(key.to_string(), *x);
                    true
                }
            },
            // Behaviours post no binary data; were one to, it would never be filtered.
            Value::Binary(_) => true,
        }
    }
    pub(super) fn clear(&mut self) {
        self.text.clear();
        self.num.clear();
    }
}
