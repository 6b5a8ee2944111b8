;; tablewclear, corrected: seed 002's domain (tablewclear-domain.pddl) with
;; (not (removed ?o)) added to every action's precondition, so no plan grasps or
;; pushes an object that is already in the bin. Optimal plans are the same length
;; (re-grasping or pushing a removed object never helps); satisficing planners can no
;; longer waste actions on removed objects. tabula's clearing pipeline uses this one.
(define (domain tablewclear)
  (:requirements :strips :typing :negative-preconditions
                 :existential-preconditions :universal-preconditions
                 :conditional-effects)
  (:types obj)
  (:predicates
    (removed ?o - obj)
    (on ?o1 - obj ?o2 - obj)            ; ?o1 stands on ?o2
    (block_grasp ?o1 - obj ?o2 - obj)   ; ?o1 blocks grasping ?o2
    (block_dir1 ?o1 - obj ?o2 - obj)    ; ?o1 blocks pushing ?o2 along dir 1
    (block_dir2 ?o1 - obj ?o2 - obj)
    (block_dir3 ?o1 - obj ?o2 - obj)
    (block_dir4 ?o1 - obj ?o2 - obj)
    (ik_unfeasible_dir1 ?o - obj)
    (ik_unfeasible_dir2 ?o - obj)
    (ik_unfeasible_dir3 ?o - obj)
    (ik_unfeasible_dir4 ?o - obj)
    (ik_unfeasible_grasp ?o - obj))

  (:action grasp
    :parameters (?o - obj)
    :precondition (and
        (not (removed ?o))
        (not (ik_unfeasible_grasp ?o))
        (not (exists (?x - obj) (on ?x ?o)))
        (not (exists (?x - obj) (block_grasp ?x ?o))))
    :effect (and
        (removed ?o)
        (forall (?x - obj) (when (on ?o ?x) (not (on ?o ?x))))
        (forall (?x - obj) (when (block_grasp ?o ?x) (not (block_grasp ?o ?x))))
        (forall (?x - obj) (when (block_dir1 ?o ?x) (not (block_dir1 ?o ?x))))
        (forall (?x - obj) (when (block_dir2 ?o ?x) (not (block_dir2 ?o ?x))))
        (forall (?x - obj) (when (block_dir3 ?o ?x) (not (block_dir3 ?o ?x))))
        (forall (?x - obj) (when (block_dir4 ?o ?x) (not (block_dir4 ?o ?x))))))

  (:action push_dir1
    :parameters (?o - obj)
    :precondition (and
        (not (removed ?o))
        (not (ik_unfeasible_dir1 ?o))
        (not (exists (?x - obj) (block_dir1 ?x ?o)))
        (not (exists (?x - obj) (on ?x ?o)))
        (not (exists (?x - obj) (on ?o ?x))))
    :effect (and
        (forall (?x - obj) (and
          (when (block_dir1 ?o ?x) (not (block_dir1 ?o ?x)))
          (when (block_dir2 ?o ?x) (not (block_dir2 ?o ?x)))
          (when (block_dir3 ?o ?x) (not (block_dir3 ?o ?x)))
          (when (block_dir4 ?o ?x) (not (block_dir4 ?o ?x)))
          (when (block_dir1 ?x ?o) (not (block_dir1 ?x ?o)))
          (when (block_dir2 ?x ?o) (not (block_dir2 ?x ?o)))
          (when (block_dir3 ?x ?o) (not (block_dir3 ?x ?o)))
          (when (block_dir4 ?x ?o) (not (block_dir4 ?x ?o)))
          (when (block_grasp ?x ?o) (not (block_grasp ?x ?o)))
          (when (block_grasp ?o ?x) (not (block_grasp ?o ?x)))))
        (when (ik_unfeasible_grasp ?o) (not (ik_unfeasible_grasp ?o)))))

  (:action push_dir2
    :parameters (?o - obj)
    :precondition (and
        (not (removed ?o))
        (not (ik_unfeasible_dir2 ?o))
        (not (exists (?x - obj) (block_dir2 ?x ?o)))
        (not (exists (?x - obj) (on ?x ?o)))
        (not (exists (?x - obj) (on ?o ?x))))
    :effect (and
        (forall (?x - obj) (and
          (when (block_dir1 ?o ?x) (not (block_dir1 ?o ?x)))
          (when (block_dir2 ?o ?x) (not (block_dir2 ?o ?x)))
          (when (block_dir3 ?o ?x) (not (block_dir3 ?o ?x)))
          (when (block_dir4 ?o ?x) (not (block_dir4 ?o ?x)))
          (when (block_dir1 ?x ?o) (not (block_dir1 ?x ?o)))
          (when (block_dir2 ?x ?o) (not (block_dir2 ?x ?o)))
          (when (block_dir3 ?x ?o) (not (block_dir3 ?x ?o)))
          (when (block_dir4 ?x ?o) (not (block_dir4 ?x ?o)))
          (when (block_grasp ?x ?o) (not (block_grasp ?x ?o)))
          (when (block_grasp ?o ?x) (not (block_grasp ?o ?x)))))
        (when (ik_unfeasible_grasp ?o) (not (ik_unfeasible_grasp ?o)))))

  (:action push_dir3
    :parameters (?o - obj)
    :precondition (and
        (not (removed ?o))
        (not (ik_unfeasible_dir3 ?o))
        (not (exists (?x - obj) (block_dir3 ?x ?o)))
        (not (exists (?x - obj) (on ?x ?o)))
        (not (exists (?x - obj) (on ?o ?x))))
    :effect (and
        (forall (?x - obj) (and
          (when (block_dir1 ?o ?x) (not (block_dir1 ?o ?x)))
          (when (block_dir2 ?o ?x) (not (block_dir2 ?o ?x)))
          (when (block_dir3 ?o ?x) (not (block_dir3 ?o ?x)))
          (when (block_dir4 ?o ?x) (not (block_dir4 ?o ?x)))
          (when (block_dir1 ?x ?o) (not (block_dir1 ?x ?o)))
          (when (block_dir2 ?x ?o) (not (block_dir2 ?x ?o)))
          (when (block_dir3 ?x ?o) (not (block_dir3 ?x ?o)))
          (when (block_dir4 ?x ?o) (not (block_dir4 ?x ?o)))
          (when (block_grasp ?x ?o) (not (block_grasp ?x ?o)))
          (when (block_grasp ?o ?x) (not (block_grasp ?o ?x)))))
        (when (ik_unfeasible_grasp ?o) (not (ik_unfeasible_grasp ?o)))))

  (:action push_dir4
    :parameters (?o - obj)
    :precondition (and
        (not (removed ?o))
        (not (ik_unfeasible_dir4 ?o))
        (not (exists (?x - obj) (block_dir4 ?x ?o)))
        (not (exists (?x - obj) (on ?x ?o)))
        (not (exists (?x - obj) (on ?o ?x))))
    :effect (and
        (forall (?x - obj) (and
          (when (block_dir1 ?o ?x) (not (block_dir1 ?o ?x)))
          (when (block_dir2 ?o ?x) (not (block_dir2 ?o ?x)))
          (when (block_dir3 ?o ?x) (not (block_dir3 ?o ?x)))
          (when (block_dir4 ?o ?x) (not (block_dir4 ?o ?x)))
          (when (block_dir1 ?x ?o) (not (block_dir1 ?x ?o)))
          (when (block_dir2 ?x ?o) (not (block_dir2 ?x ?o)))
          (when (block_dir3 ?x ?o) (not (block_dir3 ?x ?o)))
          (when (block_dir4 ?x ?o) (not (block_dir4 ?x ?o)))
          (when (block_grasp ?x ?o) (not (block_grasp ?x ?o)))
          (when (block_grasp ?o ?x) (not (block_grasp ?o ?x)))))
        (when (ik_unfeasible_grasp ?o) (not (ik_unfeasible_grasp ?o)))))
)
