//! Test harness: a simple kinematic vehicle and a lockstep loop around the helm.
#![allow(dead_code)]

use helm::{Helm, Mail, Posting, Value};

/// A point-mass vehicle: turns toward the desired heading at a fixed rate and approaches the
/// desired speed with a fixed acceleration.
#[derive(Debug, Clone)]
pub struct Vehicle {
    pub x: f64,
    pub y: f64,
    pub heading: f64,
    pub speed: f64,
    pub turn_rate: f64,
    pub accel: f64,
}

impl Vehicle {
    pub fn new(x: f64, y: f64, heading: f64) -> Self {
        Vehicle {
            x,
            y,
            heading,
            speed: 0.0,
            turn_rate: 40.0,
            accel: 0.5,
        }
    }

    pub fn step(&mut self, dt: f64, des_heading: f64, des_speed: f64) {
        let mut err = (des_heading - self.heading) % 360.0;
        if err > 180.0 {
            err -= 360.0;
        }
        if err < -180.0 {
            err += 360.0;
        }
        let max = self.turn_rate * dt;
        self.heading = (self.heading + err.clamp(-max, max)).rem_euclid(360.0);
        let dv = (des_speed - self.speed).clamp(-self.accel * dt, self.accel * dt);
        self.speed += dv;
        let r = self.heading.to_radians();
        self.x += r.sin() * self.speed * dt;
        self.y += r.cos() * self.speed * dt;
    }

    pub fn nav_mail(&self, t: f64) -> Vec<Mail> {
        vec![
            Mail::new("NAV_X", self.x, t).from("uSimMarine"),
            Mail::new("NAV_Y", self.y, t).from("uSimMarine"),
            Mail::new("NAV_HEADING", self.heading, t).from("uSimMarine"),
            Mail::new("NAV_SPEED", self.speed, t).from("uSimMarine"),
        ]
    }
}

/// Lockstep loop: the vehicle, the helm, and the helm's own postings fed back to it when it
/// subscribes to them (as the MOOSDB would).
pub struct Rig {
    pub helm: Helm,
    pub vehicle: Vehicle,
    pub t: f64,
    pub dt: f64,
    pub des_heading: f64,
    pub des_speed: f64,
    pub log: Vec<(f64, Posting)>,
    subs: Vec<String>,
    feedback: Vec<Mail>,
}

impl Rig {
    pub fn new(helm: Helm, vehicle: Vehicle) -> Self {
        let subs = helm.subscriptions().to_vec();
        Rig {
            helm,
            vehicle,
            t: 0.0,
            dt: 0.25,
            des_heading: 0.0,
            des_speed: 0.0,
            log: Vec::new(),
            subs,
            feedback: Vec::new(),
        }
    }

    /// One step: vehicle moves with the last decision, nav mail + feedback + `extra` mail go
    /// to the helm, the helm iterates. Returns this step's postings.
    pub fn step(&mut self, extra: &[Mail]) -> Vec<Posting> {
        self.vehicle.step(self.dt, self.des_heading, self.des_speed);
        self.t += self.dt;
        let t = self.t;
        let mut mail = std::mem::take(&mut self.feedback);
        mail.extend(self.vehicle.nav_mail(t));
        mail.extend_from_slice(extra);
        self.helm.on_mail(&mail);
        let posts = self.helm.iterate(t).to_vec();
        for p in &posts {
            match (&*p.key, &p.value) {
                ("DESIRED_HEADING", Value::Double(v)) => self.des_heading = *v,
                ("DESIRED_SPEED", Value::Double(v)) => self.des_speed = *v,
                _ => {}
            }
            if self.subs.iter().any(|s| *s == *p.key) {
                let mut m = Mail::new(&p.key, p.value.clone(), t).from("pHelmIvP");
                m.source_aux = p.aux.clone();
                self.feedback.push(m);
            }
            self.log.push((t, p.clone()));
        }
        posts
    }

    /// Steps until `pred` holds on a step's postings (returns them) or `max_secs` pass (panics).
    pub fn run_until(
        &mut self,
        max_secs: f64,
        what: &str,
        pred: impl Fn(&[Posting]) -> bool,
    ) -> Vec<Posting> {
        let end = self.t + max_secs;
        while self.t < end {
            let posts = self.step(&[]);
            if pred(&posts) {
                return posts;
            }
        }
        panic!(
            "{what}: not seen within {max_secs} s (t = {}, vehicle at {:.1},{:.1})",
            self.t, self.vehicle.x, self.vehicle.y
        );
    }
}

pub fn get<'a>(posts: &'a [Posting], var: &str) -> Option<&'a Value> {
    posts.iter().find(|p| p.key == var).map(|p| &p.value)
}

pub fn all<'a>(posts: &'a [Posting], var: &str) -> Vec<&'a Value> {
    posts
        .iter()
        .filter(|p| p.key == var)
        .map(|p| &p.value)
        .collect()
}

pub fn is_str(v: Option<&Value>, s: &str) -> bool {
    v.and_then(Value::as_str) == Some(s)
}
