#!/usr/bin/env python3
# Independent CST plane-stress solution of Cook's membrane on a structured n x n mesh (pure Python,
# banded solve): the vertical displacement of the right edge's top corner and of its midpoint.
#   cook_cst_reference.py N ...          Cook's panel (corners (0,0), (48,44), (48,60), (0,44))
#   cook_cst_reference.py --beam N ...   its check: a 48 x 12 rectangular cantilever, tip shear 1
#                                        (Timoshenko beam deflection ~269)
import sys


def cst(n, bottom, top, E=1.0, nu=1/3.0):
    """Panel 0 <= x <= 48 between the edges y = bottom(s), top(s), s = x / 48; left edge clamped,
    a total shear 1 spread uniformly over the right edge."""
    X=[]
    for j in range(n+1):
        for i in range(n+1):
            s=i/n; t=j/n; yb=bottom(s); yt=top(s)
            X.append((48*s, yb+t*(yt-yb)))
    N=len(X); idx=lambda i,j:j*(n+1)+i
    tris=[]
    for j in range(n):
        for i in range(n):
            a,b,c,d=idx(i,j),idx(i+1,j),idx(i+1,j+1),idx(i,j+1)
            tris+=[(a,b,c),(a,c,d)]
    f=E/(1-nu*nu); D=[[f,f*nu,0],[f*nu,f,0],[0,0,f*(1-nu)/2]]
    nd=2*N; bw=2*(n+2)+2
    K=[dict() for _ in range(nd)]
    for t in tris:
        (x1,y1),(x2,y2),(x3,y3)=[X[k] for k in t]
        A=0.5*((x2-x1)*(y3-y1)-(x3-x1)*(y2-y1))
        b=[y2-y3,y3-y1,y1-y2]; c=[x3-x2,x1-x3,x2-x1]
        B=[[0]*6 for _ in range(3)]
        for k in range(3):
            B[0][2*k]=b[k]/(2*A);B[1][2*k+1]=c[k]/(2*A);B[2][2*k]=c[k]/(2*A);B[2][2*k+1]=b[k]/(2*A)
        DB=[[sum(D[r][q]*B[q][col] for q in range(3)) for col in range(6)] for r in range(3)]
        dofs=[2*t[0],2*t[0]+1,2*t[1],2*t[1]+1,2*t[2],2*t[2]+1]
        for a_ in range(6):
            for b_ in range(6):
                v=A*sum(B[r][a_]*DB[r][b_] for r in range(3))
                K[dofs[a_]][dofs[b_]]=K[dofs[a_]].get(dofs[b_],0.0)+v
    F=[0.0]*nd
    height=top(1.0)-bottom(1.0)
    for j in range(n):
        a,b=idx(n,j),idx(n,j+1); L=X[b][1]-X[a][1]
        F[2*a+1]+=0.5*L/height; F[2*b+1]+=0.5*L/height
    fixed=set()
    for j in range(n+1): fixed|={2*idx(0,j),2*idx(0,j)+1}
    for k in fixed:
        K[k]={k:1.0}; F[k]=0.0
        for r in range(nd):
            if r!=k and k in K[r]: del K[r][k]
    # banded Gaussian elimination (symmetric positive definite, no pivoting)
    for k in range(nd):
        piv=K[k][k]
        for r in range(k+1,min(nd,k+bw+1)):
            if k in K[r]:
                m=K[r][k]/piv
                for col,v in K[k].items():
                    if col>=k: K[r][col]=K[r].get(col,0.0)-m*v
                F[r]-=m*F[k]
    u=[0.0]*nd
    for k in range(nd-1,-1,-1):
        s=F[k]-sum(v*u[col] for col,v in K[k].items() if col>k)
        u[k]=s/K[k][k]
    return u[2*idx(n,n)+1], u[2*idx(n,n//2)+1]


if __name__ == "__main__":
    beam = "--beam" in sys.argv
    for n in (int(a) for a in sys.argv[1:] if a != "--beam"):
        if beam:
            print(n, "tip", cst(n, lambda s: 0.0, lambda s: 12.0)[0])
        else:
            corner, mid = cst(n, lambda s: 44*s, lambda s: 44+16*s)
            print(n, "corner", corner, "midpoint", mid)
