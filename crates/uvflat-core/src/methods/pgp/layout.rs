//! Chart layout of a PGP parameterization (Ray et al. 2006, §3.3): the chart boundaries are
//! the iso-2kπ lines of θ and φ, built by Algorithm 2 ([`super::isolines`] at one line per
//! period), given here as polylines on the surface between chart corners, and the charts are
//! the faces they bound (with their number of corners: four for a regular chart).
//!
//! The per-chart parameterization of §3.4 (the chart boundaries inserted into the
//! triangulation, charts assembled or re-parameterized) is [`super::charts`].

use super::isolines::{iso_graph, IsoGraph};
use super::remesh::corner_nodes;
use super::PgpResult;
use crate::error::Result;
use crate::mesh::NONE;
use crate::TriMesh;

/// Chart boundaries and charts.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ChartLayout {
    /// Boundary polylines: points on the surface from one chart corner to the next (the first
    /// point repeated at the end for a closed line without corners).
    pub polylines: Vec<Vec<[f64; 3]>>,
    /// Number of corners of every chart.
    pub chart_corners: Vec<u32>,
}

/// The chart layout of §3.3.
pub fn chart_layout(mesh: &TriMesh, result: &PgpResult) -> Result<ChartLayout> {
    let graph = iso_graph(mesh, result, 1.0)?;
    let corner = corner_nodes(&graph);
    let polylines = polylines(&graph, &corner);
    let chart_corners =
        graph.faces().iter().map(|f| f.iter().filter(|&&(v, _)| corner[v as usize]).count() as u32).collect();
    Ok(ChartLayout { polylines, chart_corners })
}

/// Every graph edge once, chained through the nodes that are not corners.
fn polylines(graph: &IsoGraph, corner: &[bool]) -> Vec<Vec<[f64; 3]>> {
    let mut used: Vec<Vec<bool>> = graph.arms.iter().map(|a| vec![false; a.len()]).collect();
    let mut lines = Vec::new();
    // Lines from corners first, then closed loops through non-corners only.
    for pass in 0..2 {
        for v in 0..graph.arms.len() {
            if (pass == 0) != corner[v] {
                continue;
            }
            for s in 0..graph.arms[v].len() {
                if graph.arms[v][s].to != NONE && !used[v][s] {
                    lines.push(walk(graph, corner, &mut used, v, s));
                }
            }
        }
    }
    lines
}

/// Follows arm `s` of `v` until a corner or back to `v`.
fn walk(graph: &IsoGraph, corner: &[bool], used: &mut [Vec<bool>], v0: usize, s0: usize) -> Vec<[f64; 3]> {
    let mut line = vec![graph.position[v0]];
    let (mut v, mut s) = (v0, s0);
    loop {
        let arm = graph.arms[v][s];
        used[v][s] = true;
        used[arm.to as usize][arm.back as usize] = true;
        v = arm.to as usize;
        line.push(graph.position[v]);
        if corner[v] || v == v0 {
            return line;
        }
        // Continue through the other arm of a pass-through node.
        match graph.other_arm(v, arm.back as usize) {
            Some(k) if !used[v][k] => s = k,
            _ => return line,
        }
    }
}
