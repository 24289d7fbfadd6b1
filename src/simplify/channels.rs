//! Which attribute channels the simplifier prices, a step of the set-up before the quadrics.
//!
//! Hoppe's attribute quadrics cost a gradient per face and channel and a Schur-complement update
//! per pricing and channel, so every channel priced for nothing is work on every collapse. Two
//! kinds of channel need no quadric of their own, and leaving them out changes no cost:
//! - a **constant** channel (every vertex has the same value, e.g. a colour's alpha of 1) has a
//!   zero gradient on every face, so it adds no error; interpolating it keeps the constant;
//! - a **duplicate** channel (equal to an earlier channel at every vertex, e.g. the green and blue
//!   of a grey vertex colour) has the same gradients as that channel, so its error is that
//!   channel's scaled by the weight ratio: pricing the earlier channel once with both weights
//!   summed gives the same error, and the duplicate takes the earlier channel's new values.
//!
//! Channels with weight 0 are not priced either; their values are interpolated along the
//! collapsed edge.

/// The priced channels and where every channel's new values come from.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Channels {
    /// Per priced channel: the input channel it reads and its weight (a duplicate's added).
    pub priced: Vec<(usize, f32)>,
    /// Per input channel: the priced channel whose optimal value it takes, or `None` to be
    /// interpolated (weight 0, or constant).
    pub source: Vec<Option<usize>>,
}

impl Channels {
    /// Plans the channels of `attributes` (`weights.len()` floats per vertex).
    pub fn new(attributes: &[f32], weights: &[f32]) -> Channels {
        let m = weights.len();
        let vertex_count = attributes.len().checked_div(m).unwrap_or(0);
        let column = |j: usize| (0..vertex_count).map(move |v| attributes[v * m + j]);
        let mut priced: Vec<(usize, f32)> = Vec::new();
        let mut source = vec![None; m];
        for j in 0..m {
            // Validated input has no negative or NaN weight: 0 is the only unpriced one.
            if weights[j] == 0.0 {
                continue;
            }
            let first = column(j).next();
            if column(j).all(|x| Some(x) == first) {
                continue; // constant (or no vertices): no gradient anywhere
            }
            // Bitwise equality: two channels are merged only when their values are identical.
            let same =
                |(i, _): &(usize, f32)| column(*i).zip(column(j)).all(|(a, b)| a.to_bits() == b.to_bits());
            match priced.iter().position(same) {
                Some(k) => {
                    priced[k].1 += weights[j];
                    source[j] = Some(k);
                }
                None => {
                    source[j] = Some(priced.len());
                    priced.push((j, weights[j]));
                }
            }
        }
        Channels { priced, source }
    }

    /// Floats per wedge in the attribute sums: `Σ area`, then `(gx, gy, gz, d)` per priced channel.
    pub fn stride(&self) -> usize {
        1 + 4 * self.priced.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn constant_duplicate_and_unweighted_channels_are_not_priced() {
        // Channels: varying, constant, duplicate of 0, weight 0, varying, duplicate of 4.
        let attributes = [
            0.1, 1.0, 0.1, 5.0, 0.3, 0.3, //
            0.2, 1.0, 0.2, 6.0, 0.1, 0.1, //
            0.4, 1.0, 0.4, 7.0, 0.2, 0.2,
        ];
        let channels = Channels::new(&attributes, &[1.0, 2.0, 0.5, 0.0, 3.0, 0.25]);
        assert_eq!(channels.priced, [(0, 1.5), (4, 3.25)]);
        assert_eq!(channels.source, [Some(0), None, Some(0), None, Some(1), Some(1)]);
        assert_eq!(channels.stride(), 9);
    }

    #[test]
    fn a_channel_equal_only_at_some_vertices_stays_its_own() {
        let attributes = [0.1, 0.1, 0.2, 0.3];
        let channels = Channels::new(&attributes, &[1.0, 1.0]);
        assert_eq!(channels.priced, [(0, 1.0), (1, 1.0)]);
        assert_eq!(Channels::new(&[], &[]).stride(), 1);
    }
}
