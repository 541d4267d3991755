% A family tree, written for planerel's tests.

% ancestor/2 is recursive: the target appears in its own determinations.
:- set(i, 2).
:- set(clauselength, 3).

:- modeh(1, ancestor(+person, +person)).
:- modeb(*, parent(+person, -person)).
:- modeb(*, ancestor(+person, -person)).

:- determination(ancestor/2, parent/2).
:- determination(ancestor/2, ancestor/2).

person(andrew).
person(anne).
person(beatrice).
person(charles).
person(charlotte).
person(diana).
person(edward).
person(elizabeth).
person(elizabeth2).
person(eugenie).
person(george).
person(george2).
person(harry).
person(kate).
person(margaret).
person(mark).
person(mum).
person(peter).
person(philip).
person(sarah).
person(william).
person(zara).
parent(george, mum).
parent(george, elizabeth).
parent(mum, elizabeth2).
parent(mum, margaret).
parent(elizabeth2, charles).
parent(elizabeth2, anne).
parent(elizabeth2, andrew).
parent(elizabeth2, edward).
parent(philip, charles).
parent(philip, anne).
parent(philip, andrew).
parent(philip, edward).
parent(charles, william).
parent(charles, harry).
parent(diana, william).
parent(diana, harry).
parent(anne, peter).
parent(anne, zara).
parent(mark, peter).
parent(mark, zara).
parent(andrew, beatrice).
parent(andrew, eugenie).
parent(sarah, beatrice).
parent(sarah, eugenie).
parent(william, george2).
parent(william, charlotte).
parent(kate, george2).
parent(kate, charlotte).
male(george).
male(charles).
male(andrew).
male(edward).
male(philip).
male(william).
male(harry).
male(peter).
male(mark).
male(george2).
female(anne).
female(beatrice).
female(charlotte).
female(diana).
female(elizabeth).
female(elizabeth2).
female(eugenie).
female(kate).
female(margaret).
female(mum).
female(sarah).
female(zara).
